#include "edsp/transport/decode.h"
#include "edsp/logger/measurement_export.h"

#include <algorithm>
#include <array>
#include <deque>
#include <iterator>
#include <map>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/log_reader.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

namespace {

// How late a message may reach the logger and still be paired by its own
// stamp (processes on one host deliver within milliseconds; a descheduled
// logger reads its socket backlog later, but in order of arrival).
constexpr std::int64_t kReorderWindowUs = 500'000;
// How far after its setpoint a sample may be and the command still be
// carried along to it: the bridge stops the drives' feed-forward after
// 2.5 ms without a command (kFeedForwardLapseUs).
constexpr double kLongestCarryS = 0.0025;
// Setpoints further apart than this in the log are a stream that stopped,
// not ticks missing from it: nothing is interpolated across.
constexpr std::int64_t kLongestGapUs = 50'000;
// A stall of the real-time system: longer than this between two readings
// of the drives (the bridge itself late), or between two cycles of the rig
// emulator (EDSP_RIG_TRUTH: the bridge stamps a stale image's readings
// with its own reads after 2 ms, so the readings alone show its stalls as
// ~3 ms whatever their length). The samples from a little before it to the
// drives' recovery after it are flagged `timing_event`: the drives braked
// while the commands ran on, and a torque-limited servo catches up over a
// time that grows with the distance lost (measured live at 0.25 m/s: ~70 ms
// after a 6 ms stall, ~190 ms after an 18.8 ms one, the platform 6 mm off
// 90 ms after that stall had ended).
constexpr double kStallUs = 2'500;
// Commands late while the bridge kept its time (a planner or kinematics
// tick missed) are no stall until this long: the bridge continues the last
// command's motion for 10 ms (kRideThroughUs, actuator_bridge.h), and the
// platform stays on its path.
constexpr double kCommandsSilentUs = 10'000;
// The rig emulator reports every cycle at its own instant, those it caught
// up after a late wake included (rig/physics_clock.h): two of its cycles
// further apart than 1.5 cycles lost the time between (an emulator frozen
// past its catch-up, or one that does not catch up), and its platform that
// motion (at 0.25 m/s, 125 µm per half cycle).
constexpr double kRigLateUs = 1'500;
constexpr double kFlagBeforeUs = 2'000;
constexpr double kFlagAfterUs = 100'000;
constexpr double kFlagAfterPerStalled = 10.0;    // and 10 ms more per ms stalled,
constexpr double kLongestFlagExtensionUs = 1e6;  //   at most 1 s more (a latch)

// The stalls of a log, found as its messages come, and whether a sample
// lies near one: from kFlagBeforeUs before it to the drives' recovery after
// it, or after the start of one still open (the drives' commands or
// readings stopped and never came again before the sample was written).
// Stamps are the senders' word: the arithmetic is in double.
class StallWatch {
 public:
  // A leg state: the drives' reading at `utime`, running command `seq`
  // (0: none yet). Older than the newest (reordered, repeated): ignored.
  void Reading(std::int64_t utime, std::int64_t seq) {
    if (seq == 0 || utime < newest_reading_) return;
    if (newest_reading_ != 0) Gap(newest_reading_, utime);
    newest_reading_ = utime;
    if (seq == command_seq_) return;
    if (command_seq_ != 0) Gap(command_since_, utime, kCommandsSilentUs);
    command_seq_ = seq;
    command_since_ = utime;
  }
  // A cycle of the rig emulator at `utime`.
  void RigCycle(std::int64_t utime) {
    if (utime <= newest_cycle_) return;
    if (newest_cycle_ != 0) Gap(newest_cycle_, utime, kRigLateUs);
    newest_cycle_ = utime;
  }
  // Any other instant the log vouches for (a tracker sample's): readings
  // that stopped before it stopped for good, so far.
  void Heard(std::int64_t utime) { newest_heard_ = std::max(newest_heard_, utime); }
  // Samples come in order of their stamps.
  bool Near(std::int64_t utime) {
    const double t = static_cast<double>(utime);
    while (!stalls_.empty() && RecoveredBy(stalls_.front()) < t) stalls_.pop_front();
    for (const Stall& s : stalls_) {
      if (s.from - kFlagBeforeUs <= t && t <= RecoveredBy(s)) return true;
    }
    const double since_command = static_cast<double>(command_since_);
    const double newest = static_cast<double>(newest_reading_);
    return Open(since_command, newest, t, kCommandsSilentUs) || Open(newest, static_cast<double>(newest_heard_), t);
  }

 private:
  struct Stall {
    double from, to;
  };
  void Gap(std::int64_t from, std::int64_t to, double longest_us = kStallUs) {
    const Stall s{static_cast<double>(from), static_cast<double>(to)};
    if (s.to - s.from > longest_us) stalls_.push_back(s);
  }
  static double RecoveredBy(const Stall& s) {
    return s.to + kFlagAfterUs + std::min(kFlagAfterPerStalled * (s.to - s.from), kLongestFlagExtensionUs);
  }
  // Nothing new since `since` by `newest` (0: never anything): open from it.
  static bool Open(double since, double newest, double t, double longest_us = kStallUs) {
    return since != 0.0 && newest - since > longest_us && t >= since - kFlagBeforeUs;
  }

  std::deque<Stall> stalls_;
  std::int64_t newest_reading_ = 0, command_seq_ = 0, command_since_ = 0, newest_cycle_ = 0, newest_heard_ = 0;
};

template <typename Msg>
bool Decode(const LogEvent& event, Msg* msg) {
  return DecodeUntrusted(msg, event.data.data(), event.data.size());
}

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
    const bool stalled = stalls_.Near(point.utime);
    out_ << fmt::format(",{:.17g},{:.17g},{:.17g},{}\n", point.point_m[0], point.point_m[1], point.point_m[2],
                        stalled ? 1 : 0);
    ++result->rows;
    result->timing_events += stalled ? 1 : 0;
    TrimBefore(&setpoints_, point.utime);
    TrimBefore(&legs_, point.utime);
    commands_.erase(commands_.begin(), command);
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
      if (Decode(event, &setpoint)) pairing.Add(setpoint);
    } else if (event.channel == channel::kLegCommand) {
      leg_command_t command;
      if (Decode(event, &command)) pairing.Add(command);
    } else if (event.channel == channel::kLegState) {
      leg_state_t legs;
      if (Decode(event, &legs)) pairing.Add(legs);
    } else if (event.channel == channel::kRigTruth) {
      rig_truth_t truth;
      if (Decode(event, &truth)) pairing.Add(truth);
    } else if (event.channel == channel::kTracker) {
      tracker_point_t point{};
      if (Decode(event, &point))
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
