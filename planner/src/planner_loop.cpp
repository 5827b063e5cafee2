#include "edsp/planner/planner_loop.h"

#include <cmath>
#include "edsp/channels.h"

namespace edsp {

PlannerLoop::PlannerLoop(Bus& bus, Planner& planner, PlannerLoopOptions options)
    : planner_(planner),
      options_(options),
      setpoints_(bus.Advertise<pose_setpoint_t>(channel::kSetpoint)),
      status_out_(bus.Advertise<node_status_t>(channel::kStatus)) {
  status_.SetState(node_status_t::STATE_RUNNING);
}

void PlannerLoop::Start(std::int64_t start_utime) {
  start_utime_ = start_utime;
  planner_.Start(start_utime);
}

bool PlannerLoop::RunCycle(std::int64_t now_utime, std::int64_t deadline_misses) {
  const auto began = std::chrono::steady_clock::now();
  if (setpoints_.Publish(planner_.Step(now_utime))) status_.CountOut();
  bool go_on = true;
  if (planner_.Finished(now_utime)) {
    status_.SetState(node_status_t::STATE_HOLDING);
    // In whole microseconds, as the clock: the last cycle is the one the sum says.
    const std::int64_t end_utime =
        start_utime_ + std::llround((planner_.sequence().duration_s() + options_.exit_after_hold_s) * 1e6);
    go_on = options_.exit_after_hold_s < 0.0 || now_utime < end_utime;
  }
  status_.RecordLoop(std::chrono::steady_clock::now() - began);
  if (status_.Due(now_utime)) status_out_.Publish(status_.Report(now_utime, deadline_misses));
  return go_on;
}

void PlannerLoop::Run(CycleClock& clock, const std::function<bool()>& stop) {
  Start(UtimeNow());
  while (!stop()) {
    clock.WaitNext();
    if (!RunCycle(UtimeNow(), clock.missed())) break;
  }
}

}  // namespace edsp
