#include "edsp/logger/measurement_export.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <iterator>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/logged_message.h"
#include "edsp/logger/stall_watch.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/timing_contract.h"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

namespace {

// How late a message may reach the logger and still be paired by its own
// stamp (processes on one host deliver within milliseconds; a descheduled
// logger reads its socket backlog later, but in order of arrival).
constexpr std::int64_t kReorderWindowUs = 500'000;
// How far after its setpoint a sample may be and the command still be
// carried along to it: the drives continue a setpoint by themselves for the
// feed-forward lapse, past which the bridge writes its own, and a setpoint
// the log lacks is better taken between its neighbours.
constexpr double kLongestCarryS = timing::kFeedForwardLapseS;
// Setpoints further apart than this in the log are a stream that stopped,
// not ticks missing from it: nothing is interpolated across.
constexpr std::int64_t kLongestGapUs = 50'000;
void WriteHeader(std::ostream& out) {
  out << "time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
         "pose_cmd_yaw_rad";
  for (int i = 1; i <= 6; ++i) out << ",leg_cmd_" << i << "_m";
  for (int i = 1; i <= 6; ++i) out << ",leg_enc_" << i << "_m";
  for (int i = 1; i <= 6; ++i) out << ",leg_corr_" << i << "_m";
  out << ",point_x_m,point_y_m,point_z_m,timing_event\n";
}

struct Stamped6 {
  std::int64_t utime = 0;
  std::array<double, 6> values{};
};

struct Setpoint {
  std::int64_t utime = 0;
  std::array<double, 6> pose{}, velocity{};
  std::string run;
};

// A leg command: the lengths for the drives, and the calibration's
// correction taken off them (the leg command's own fields say it:
// command = IK − PR − correction).
struct Command {
  std::array<double, 6> legs{}, correction{};
};

struct PendingSample {
  std::int64_t received_utime = 0;
  tracker_point_t point;
};

// Keeps `items` in order of utime as they arrive (nearly in order already);
// equal stamps keep their order of arrival.
template <typename T>
void InsertByUtime(std::deque<T>* items, T item) {
  auto at = items->end();
  while (at != items->begin() && std::prev(at)->utime > item.utime) --at;
  items->insert(at, std::move(item));
}

// The last item stamped at or before `utime`, or null.
template <typename T>
const T* LastAtOrBefore(const std::deque<T>& items, std::int64_t utime) {
  auto after =
      std::upper_bound(items.begin(), items.end(), utime, [](std::int64_t t, const T& item) { return t < item.utime; });
  return after == items.begin() ? nullptr : &*std::prev(after);
}

// Drops what no later sample can use: everything before the last item
// stamped at or before `utime` (tracker samples come in order of their stamps).
template <typename T>
void TrimBefore(std::deque<T>* items, std::int64_t utime) {
  while (items->size() > 1 && (*items)[1].utime <= utime) items->pop_front();
}

// Pairs each tracker sample (the platform at its stamp) with what the
// controller commanded for that instant: the last setpoint stamped at or
// before it, the leg command answering that setpoint, and the last encoder
// reading at or before it (the offline stack logs each step so; the live
// rig stamps a sample with the instant it describes). By the messages' own stamps, not by their order of
// arrival at the logger, which interleaves processes by a cycle or more.
class Pairing {
 public:
  explicit Pairing(std::ostream& out) : out_(out) {}

  // With no sample waiting, nothing stamped more than two windows before
  // the newest message can be needed: memory stays bounded even in a log
  // without a tracker (or with a long beam break).
  void Add(const pose_setpoint_t& s) {
    InsertByUtime(&setpoints_, Setpoint{s.utime, ToArray(s.pose), ToArray(s.velocity),
                                        s.trajectory.substr(0, s.trajectory.find('/'))});
    if (pending_.empty()) {
      TrimBefore(&setpoints_, s.utime - 2 * kReorderWindowUs);
      commands_.erase(commands_.begin(), commands_.lower_bound(setpoints_.front().utime));
    }
  }
  void Add(const leg_command_t& c) {
    Command& command = commands_[c.setpoint_utime];
    command.legs = ToArray(c.command_length_m);
    for (std::size_t i = 0; i < 6; ++i) {
      command.correction[i] = c.ik_length_m[i] - c.pr_correction_m[i] - c.command_length_m[i];
    }
  }
  void Add(const rig_truth_t& t) { stalls_.RigCycle(t.utime); }
  void Add(const leg_state_t& l) {
    stalls_.Reading(l.utime, l.command_seq);
    InsertByUtime(&legs_, Stamped6{l.utime, ToArray(l.encoder_length_m)});
    if (pending_.empty()) TrimBefore(&legs_, l.utime - 2 * kReorderWindowUs);
  }
  void Add(std::int64_t received_utime, const tracker_point_t& p) {
    stalls_.Heard(p.utime);
    pending_.push_back({received_utime, p});
  }

  // Writes the samples received before `received_utime` − the window.
  void WriteUpTo(std::int64_t received_utime, MeasurementExport* result) {
    while (!pending_.empty() && received_utime - pending_.front().received_utime > kReorderWindowUs) {
      Write(pending_.front().point, result);
      pending_.pop_front();
    }
  }
  void WriteAll(MeasurementExport* result) {
    for (; !pending_.empty(); pending_.pop_front()) Write(pending_.front().point, result);
  }

 private:
  template <typename A>
  static std::array<double, 6> ToArray(const A& a) {
    std::array<double, 6> v{};
    std::copy(std::begin(a), std::begin(a) + 6, v.begin());
    return v;
  }

  void Write(const tracker_point_t& point, MeasurementExport* result) {
    const Setpoint* setpoint = LastAtOrBefore(setpoints_, point.utime);
    // The command answering that setpoint; if it never came (refused,
    // lost), the last one answering an earlier setpoint.
    auto command = setpoint ? commands_.upper_bound(setpoint->utime) : commands_.begin();
    if (!point.valid || setpoint == nullptr || command == commands_.begin()) {
      ++result->skipped;
      return;
    }
    --command;
    const Stamped6* legs = LastAtOrBefore(legs_, point.utime);
    if (first_utime_ < 0) first_utime_ = point.utime;
    out_ << fmt::format("{:.6f},{}", static_cast<double>(point.utime - first_utime_) * 1e-6, setpoint->run);
    // At the sample's instant, which falls up to a cycle after the setpoint's
    // (the processes' cycles are not in phase): the pose along its velocity,
    // the legs between the commands answering this setpoint and the next.
    // At most a few cycles: a setpoint stream that stopped (a planner frozen
    // or gone) leaves the pose where it was, as the bridge then holds it.
    for (double q : PoseAt(point.utime, *setpoint)) out_ << fmt::format(",{:.17g}", q);
    const Command legs_cmd = CommandAt(point.utime, *setpoint, command);
    for (double v : legs_cmd.legs) out_ << fmt::format(",{:.17g}", v);
    for (int i = 0; i < 6; ++i) {
      out_ << (legs ? fmt::format(",{:.17g}", legs->values[static_cast<std::size_t>(i)]) : std::string(","));
    }
    for (double v : legs_cmd.correction) out_ << fmt::format(",{:.17g}", v);
    const bool stalled = stalls_.Near(point.utime, TrackingError(legs));
    out_ << fmt::format(",{:.17g},{:.17g},{:.17g},{}\n", point.point_m[0], point.point_m[1], point.point_m[2],
                        stalled ? 1 : 0);
    ++result->rows;
    result->timing_events += stalled ? 1 : 0;
    TrimBefore(&setpoints_, point.utime);
    TrimBefore(&legs_, point.utime);
    // The one before too: the encoders a sample is paired with may be
    // older than its setpoint, and their tracking error needs the command
    // of their own instant.
    if (command != commands_.begin()) commands_.erase(commands_.begin(), std::prev(command));
  }

  // The drives' tracking error at the reading `legs` (largest leg): its
  // encoders against the command for its instant, between the commands
  // around it. None without a reading, or before the first command.
  std::optional<double> TrackingError(const Stamped6* legs) const {
    if (legs == nullptr) return std::nullopt;
    const auto after = commands_.upper_bound(legs->utime);
    if (after == commands_.begin()) return std::nullopt;
    const auto at = std::prev(after);
    const bool between = after != commands_.end() && after->first - at->first <= kLongestGapUs;
    const double w =
        between ? static_cast<double>(legs->utime - at->first) / static_cast<double>(after->first - at->first) : 0.0;
    double largest = 0.0;
    for (std::size_t i = 0; i < 6; ++i) {
      const double commanded = at->second.legs[i] + (between ? w * (after->second.legs[i] - at->second.legs[i]) : 0.0);
      largest = std::max(largest, std::abs(commanded - legs->values[i]));
    }
    return largest;
  }

  // The commanded pose at `utime`, after `setpoint`: carried along its
  // velocity for up to kLongestCarryS; later than that (setpoints missing
  // from the log: the planner skipped ticks or the logger lost them), between
  // it and the next setpoint if one came within kLongestGapS; else where it
  // was (the stream stopped, and the bridge holds).
  std::array<double, 6> PoseAt(std::int64_t utime, const Setpoint& setpoint) const {
    const double since_s = static_cast<double>(utime - setpoint.utime) * 1e-6;
    std::array<double, 6> pose = setpoint.pose;
    if (since_s <= 0.0) return pose;
    if (since_s <= kLongestCarryS) {
      for (std::size_t k = 0; k < 6; ++k) pose[k] += setpoint.velocity[k] * since_s;
      return pose;
    }
    const auto next = std::upper_bound(setpoints_.begin(), setpoints_.end(), utime,
                                       [](std::int64_t t, const Setpoint& s) { return t < s.utime; });
    if (next == setpoints_.end() || next->utime - setpoint.utime > kLongestGapUs) return pose;
    const double w = static_cast<double>(utime - setpoint.utime) / static_cast<double>(next->utime - setpoint.utime);
    for (std::size_t k = 0; k < 6; ++k) pose[k] += w * (next->pose[k] - setpoint.pose[k]);
    return pose;
  }

  // The leg command at `utime`: between the one answering `setpoint` and
  // the one answering the next setpoint, if both came; else the first.
  Command CommandAt(std::int64_t utime, const Setpoint& setpoint,
                    std::map<std::int64_t, Command>::const_iterator command) const {
    if (utime <= setpoint.utime || command->first != setpoint.utime) return command->second;
    const auto next = std::next(command);
    if (next == commands_.end() || next->first <= utime || next->first - command->first > kLongestGapUs) {
      return command->second;
    }
    const double w = static_cast<double>(utime - command->first) / static_cast<double>(next->first - command->first);
    const auto between = [w](const std::array<double, 6>& a, const std::array<double, 6>& b) {
      std::array<double, 6> v{};
      for (std::size_t i = 0; i < 6; ++i) v[i] = a[i] + w * (b[i] - a[i]);
      return v;
    };
    return Command{between(command->second.legs, next->second.legs),
                   between(command->second.correction, next->second.correction)};
  }

  std::ostream& out_;
  std::deque<Setpoint> setpoints_;
  std::deque<Stamped6> legs_;
  std::map<std::int64_t, Command> commands_;  // by the setpoint utime they answer
  std::deque<PendingSample> pending_;
  std::int64_t first_utime_ = -1;
  StallWatch stalls_;
};

}  // namespace

MeasurementExport ExportMeasurementCsv(const std::string& log_path, std::ostream& out) {
  LogReader reader(log_path);
  MeasurementExport result;
  Pairing pairing(out);
  WriteHeader(out);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel == channel::kSetpoint) {
      pose_setpoint_t setpoint;
      if (DecodeEvent(event, &setpoint)) pairing.Add(setpoint);
    } else if (event.channel == channel::kLegCommand) {
      leg_command_t command;
      if (DecodeEvent(event, &command)) pairing.Add(command);
    } else if (event.channel == channel::kLegState) {
      leg_state_t legs;
      if (DecodeEvent(event, &legs)) pairing.Add(legs);
    } else if (event.channel == channel::kRigTruth) {
      rig_truth_t truth;
      if (DecodeEvent(event, &truth)) pairing.Add(truth);
    } else if (event.channel == channel::kTracker) {
      tracker_point_t point{};
      if (DecodeEvent(event, &point))
        pairing.Add(event.timestamp_utime, point);
      else
        ++result.skipped;
    }
    pairing.WriteUpTo(event.timestamp_utime, &result);
  }
  pairing.WriteAll(&result);
  result.damaged = reader.damaged();
  result.damage_offset = reader.damage_offset();
  return result;
}

}  // namespace edsp
