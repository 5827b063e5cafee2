#include "edsp/rig/rig_cycle.h"

#include <algorithm>
#include <cmath>

namespace edsp {

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

std::int64_t RigCycle::CatchUp(std::int64_t now, bool* failed) {
  const std::int64_t cycle_us = std::llround(cycle_s_ * 1e6);
  // First cycle, or the wall clock stepped back (a time daemon): anchor here.
  if (state_utime_ < 0 || now < state_utime_ - cycle_us) return state_utime_ = now;
  // Whole cycles to the one nearest `now`: the physics run on their own
  // exact clock (a sliver of a cycle made loads from accelerations noise).
  const std::int64_t late = (now - state_utime_ + cycle_us / 2) / cycle_us;
  const std::int64_t run = std::min<std::int64_t>(late, std::llround(kLongestCatchUpS / cycle_s_));
  for (std::int64_t k = 0; k < run; ++k) *failed = !rig_->Advance(cycle_s_) || *failed;
  // Beyond that the emulator was frozen: the emulated hardware stood.
  state_utime_ += late * cycle_us;
  return state_utime_;
}

RigCycleReport RigCycle::Step(std::int64_t now, const DriveSetpoint* command, bool enable) {
  RigCycleReport report;
  report.utime = CatchUp(now, &report.physics_failed);
  report.feedback = rig_->Feedback();
  report.truth = rig_->Truth(report.utime);
  report.tracker_due = rig_->TrackerSample(report.utime, &report.tracker);
  if (command != nullptr) rig_->SetTarget(AtCycleStart(*command, report.utime, horizon_s_), enable);
  if (rig_->watchdog_tripped() != watchdog_reported_) {
    watchdog_reported_ = rig_->watchdog_tripped();
    report.watchdog_changed = true;
  }
  report.physics_failed = !rig_->Advance(cycle_s_) || report.physics_failed;
  state_utime_ = report.utime + std::llround(cycle_s_ * 1e6);
  return report;
}

}  // namespace edsp
