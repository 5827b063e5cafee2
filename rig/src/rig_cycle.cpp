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
  pending_.reserve(128);  // up to 16 a wake, over the wakes that wait
}

const std::vector<RigCycleReport>& RigCycle::Wake(std::int64_t now, const std::vector<DriveCommand>& commands) {
  reports_.clear();
  pending_.insert(pending_.end(), commands.begin(), commands.end());
  int cycles = clock_.CyclesFor(now);
  if (cycles > 1 && !StampsOnThisClock()) {
    clock_.Lose(cycles - 1);  // no stamp says which command a missed cycle had
    cycles = 1;
  }
  if (cycles > 1 && AwaitsTheController(now, cycles)) return reports_;
  waiting_since_ = 0;
  std::size_t next = 0;  // the first command no cycle has taken
  for (int k = 0; k < cycles; ++k) {
    const std::int64_t at = clock_.at();
    reports_.push_back(k + 1 == cycles ? OwnCycle(at, &next) : MissedCycle(at, &next));
    clock_.Advance();
  }
  pending_.clear();  // the wake's own cycle took the rest
  return reports_;
}

RigCycleReport RigCycle::OwnCycle(std::int64_t at, std::size_t* next) {
  if (*next == pending_.size()) return Step(at, nullptr, false);
  const DriveCommand& newest = pending_.back();
  *next = pending_.size();
  return Step(at, &newest.setpoint, newest.enable);
}

RigCycleReport RigCycle::MissedCycle(std::int64_t at, std::size_t* next) {
  const DriveCommand* newest = nullptr;
  bool heard = false;
  while (*next < pending_.size() && pending_[*next].setpoint.utime <= at) {
    const DriveCommand& c = pending_[(*next)++];
    heard = true;
    if (Rewritten(c)) continue;
    newest = &c;
    if (!c.enable) break;  // a disable resets the drives' faults: never passed over
  }
  if (newest != nullptr) return Step(at, &newest->setpoint, newest->enable);
  if (*next < pending_.size() && Bridges(pending_[*next], at)) {
    const DriveSetpoint between = CommandBetween(last_taken_, pending_[*next].setpoint, at);
    return Step(at, &between, true);
  }
  if (heard) rig_->KeepAlive();  // a re-write passed over still came
  return Step(at, nullptr, false);
}

bool RigCycle::StampsOnThisClock() const {
  // The last cycle ran at at() − 1 cycle and took a command for the tick
  // before it, unless the controller stamps by another host's clock or had
  // stopped.
  const std::int64_t cycle = clock_.cycle_us(), last = clock_.at() - cycle;
  return taken_any_ && last_taken_.utime > 0 && last_taken_.utime >= last - 2 * cycle && last_taken_.utime <= last;
}

bool RigCycle::AwaitsTheController(std::int64_t now, int cycles) {
  std::int64_t newest = last_taken_.utime;
  for (const DriveCommand& c : pending_) newest = std::max(newest, c.setpoint.utime);
  const std::int64_t own = clock_.at() + (cycles - 1) * clock_.cycle_us();
  // On time the newest command is for the tick before the own cycle.
  if (newest >= own - clock_.cycle_us() * 3 / 2) return false;
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
  report.watchdog_tripped = rig_->watchdog_tripped();
  report.since_command_s = rig_->since_command_s();
  if (report.watchdog_tripped != watchdog_reported_) {
    watchdog_reported_ = report.watchdog_tripped;
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
