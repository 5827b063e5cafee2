#include "edsp/sim/dwell_errors.h"

#include "edsp/channels.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/logger/logged_message.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

namespace {

struct TrackerSample {
  std::int64_t utime;
  Vector3 point;
};

// One dwell as it is being read: its setpoints' time span and the tracker
// samples that arrived meanwhile.
struct OpenDwell {
  pose_setpoint_t setpoint;
  std::int64_t first_utime = 0;
  std::int64_t last_utime = 0;
  std::int8_t pr_mode = 0;
  std::vector<TrackerSample> samples;
};

bool IsDwell(const pose_setpoint_t& s) { return s.phase == pose_setpoint_t::PHASE_DWELL; }

bool Close(const OpenDwell& open, const PlatformModel& model, double fraction, DwellError* out) {
  const double span = static_cast<double>(open.last_utime - open.first_utime);
  const auto from = open.last_utime - static_cast<std::int64_t>(fraction * span);
  Vector3 sum = Vector3::Zero();
  int n = 0;
  for (const TrackerSample& s : open.samples) {
    if (s.utime < from) continue;
    sum += s.point;
    ++n;
  }
  if (n == 0) return false;
  const pose_setpoint_t& sp = open.setpoint;
  out->segment = sp.trajectory;
  out->motion = sp.trajectory.substr(0, sp.trajectory.find('/'));
  out->pr_mode = static_cast<PrMode>(open.pr_mode);
  for (int k = 0; k < 6; ++k) out->target(k) = sp.pose[k];
  const int axis = MotionAxis(out->motion);
  out->displacement = axis < 0 ? 0.0 : out->target(axis) - model.home_pose().ToVector()(axis);
  out->error_m = sum / n - model.ObservationPoint(Pose::FromVector(out->target));
  out->samples = n;
  out->averaged_from_utime = from;
  out->averaged_to_utime = open.last_utime;
  return true;
}

}  // namespace

int MotionAxis(const std::string& motion) {
  static const char* const kNames[] = {"Lx", "Ly", "Lz", "Rx", "Ry", "Rz"};
  for (int k = 0; k < 6; ++k) {
    if (motion == kNames[k]) return k;
  }
  return -1;
}

DwellErrors DwellErrorsFromLog(const std::string& log_path, const PlatformModel& model, double averaged_fraction) {
  LogReader reader(log_path);
  DwellErrors result;
  OpenDwell open;
  bool in_dwell = false;
  std::int8_t pr_mode = 0;
  auto close = [&] {
    DwellError e;
    if (in_dwell && Close(open, model, averaged_fraction, &e)) result.dwells.push_back(e);
    in_dwell = false;
  };
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel == channel::kLegCommand) {
      leg_command_t c;
      if (DecodeEvent(event, &c)) pr_mode = c.pr_mode;
    } else if (event.channel == channel::kTracker) {
      tracker_point_t t;
      if (in_dwell && DecodeEvent(event, &t) && t.valid) {
        open.samples.push_back({t.utime, Vector3(t.point_m[0], t.point_m[1], t.point_m[2])});
      }
    } else if (event.channel == channel::kSetpoint) {
      pose_setpoint_t sp;
      if (!DecodeEvent(event, &sp)) continue;
      const bool same = in_dwell && sp.segment == open.setpoint.segment && sp.trajectory == open.setpoint.trajectory;
      if (same) {
        open.last_utime = sp.utime;
        open.pr_mode = pr_mode;
        continue;
      }
      close();
      if (IsDwell(sp)) {
        open = OpenDwell{sp, sp.utime, sp.utime, pr_mode, {}};
        in_dwell = true;
      }
    }
  }
  // A dwell still open at the end was cut short (the run stopped): not a stop.
  result.damaged = reader.damaged();
  result.damage_offset = reader.damage_offset();
  return result;
}

}  // namespace edsp
