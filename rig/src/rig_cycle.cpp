#include "edsp/rig/rig_cycle.h"

#include <algorithm>
#include <cmath>

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

DriveSetpoint CommandBetween(const DriveSetpoint& from, const DriveSetpoint& to, std::int64_t at) {
  DriveSetpoint between = from;
  between.utime = at;
  const double h = static_cast<double>(to.utime - from.utime) * 1e-6;
  const double t = static_cast<double>(at - from.utime) * 1e-6;
  if (h <= 0.0) return to;
  for (std::size_t i = 0; i < between.motor_angle_rad.size(); ++i) {
    // θ(t) = θ0 + ω0 t + c t², through `to`'s angle at h.
    const double w0 = from.motor_velocity_rad_s[i];
    const double c = (to.motor_angle_rad[i] - from.motor_angle_rad[i] - w0 * h) / (h * h);
    between.motor_angle_rad[i] = from.motor_angle_rad[i] + w0 * t + c * t * t;
    between.motor_velocity_rad_s[i] = w0 + 2.0 * c * t;
  }
  return between;
}

RigCycle::RigCycle(VirtualRig* rig, double cycle_s, double horizon_s, int longest_catch_up)
    : rig_(rig), cycle_s_(cycle_s), horizon_s_(horizon_s), clock_(std::llround(cycle_s * 1e6), longest_catch_up) {
  reports_.reserve(static_cast<std::size_t>(longest_catch_up) + 1);
  pending_.reserve(64);
}

const std::vector<RigCycleReport>& RigCycle::Wake(std::int64_t now, const std::vector<DriveCommand>& commands) {
  reports_.clear();
  pending_.insert(pending_.end(), commands.begin(), commands.end());
  const int cycles = clock_.CyclesFor(now);
  if (cycles > 1 && AwaitsTheController(now, cycles)) return reports_;
  waiting_since_ = 0;
  std::size_t next = 0;  // the first command no cycle has taken
  for (int k = 0; k < cycles; ++k) {
    const std::int64_t at = clock_.at();
    const bool own = k + 1 == cycles;
    const DriveCommand* newest = nullptr;
    while (next < pending_.size() && (own || pending_[next].setpoint.utime <= at)) {
      const DriveCommand& c = pending_[next++];
      if (own || !Rewritten(c)) newest = &c;
    }
    if (newest != nullptr) {
      reports_.push_back(Step(at, &newest->setpoint, newest->enable));
    } else if (!own && next < pending_.size() && Bridges(pending_[next], at)) {
      const DriveSetpoint between = CommandBetween(last_taken_, pending_[next].setpoint, at);
      reports_.push_back(Step(at, &between, true));
    } else {
      reports_.push_back(Step(at, nullptr, false));
    }
    clock_.Advance();
  }
  pending_.clear();  // the wake's own cycle took the rest
  return reports_;
}

bool RigCycle::AwaitsTheController(std::int64_t now, int cycles) {
  if (!taken_any_ && pending_.empty()) return false;  // no controller yet: nothing to wait for
  const std::int64_t newest = pending_.empty() ? last_taken_.utime : pending_.back().setpoint.utime;
  const std::int64_t own = clock_.at() + (cycles - 1) * clock_.cycle_us();
  // On time the newest command is for the tick before the own cycle; an
  // unstamped one cannot say how far the controller got.
  if (newest <= 0 || newest >= own - clock_.cycle_us() * 3 / 2) return false;
  if (waiting_since_ == 0) waiting_since_ = now;
  return now - waiting_since_ <= kLongestWaitUs;
}

bool RigCycle::Rewritten(const DriveCommand& c) const {
  return taken_any_ && c.setpoint.utime > 0 && c.setpoint.utime <= last_taken_.utime;
}

bool RigCycle::Bridges(const DriveCommand& after, std::int64_t at) const {
  const std::int64_t from = last_taken_.utime, to = after.setpoint.utime;
  return taken_any_ && last_enable_ && after.enable && from > 0 && from < at && at < to &&
         to - from <= kLongestBridgedGapUs;
}

RigCycleReport RigCycle::Step(std::int64_t now, const DriveSetpoint* command, bool enable) {
  RigCycleReport report;
  report.utime = now;
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
