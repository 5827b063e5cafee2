#include "edsp/rig/rig_cycle.h"

#include <algorithm>

namespace edsp {

namespace {

bool SameCommand(const DriveSetpoint& a, const DriveSetpoint& b) {
  return a.utime == b.utime && a.motor_angle_rad == b.motor_angle_rad &&
         a.motor_velocity_rad_s == b.motor_velocity_rad_s;
}

}  // namespace

DriveSetpoint AtCycleStart(const DriveSetpoint& command, std::int64_t now, double horizon_s) {
  DriveSetpoint at = command;
  if (command.utime <= 0) return at;
  const double late_s = std::clamp(static_cast<double>(now - command.utime) * 1e-6, 0.0, horizon_s);
  for (std::size_t i = 0; i < at.motor_angle_rad.size(); ++i) {
    at.motor_angle_rad[i] += command.motor_velocity_rad_s[i] * late_s;
  }
  at.utime = now;
  return at;
}

RigCycleReport RigCycle::Step(std::int64_t now, const DriveSetpoint* command, bool enable) {
  RigCycleReport report;
  report.feedback = rig_->Feedback();
  report.truth = rig_->Truth(now);
  report.tracker_due = rig_->TrackerSample(now, &report.tracker);
  if (command != nullptr) Take(now, *command, enable);
  if (rig_->watchdog_tripped() != watchdog_reported_) {
    watchdog_reported_ = rig_->watchdog_tripped();
    report.watchdog_changed = true;
  }
  report.physics_failed = !rig_->Advance(cycle_s_);
  return report;
}

void RigCycle::Take(std::int64_t now, const DriveSetpoint& command, bool enable) {
  if (taken_any_ && enable == last_enable_ && SameCommand(command, last_taken_)) {
    rig_->KeepAlive();
    return;
  }
  rig_->SetTarget(AtCycleStart(command, now, horizon_s_), enable);
  taken_any_ = true;
  last_taken_ = command;
  last_enable_ = enable;
}

}  // namespace edsp
