#pragma once
// The planner on a bus: EDSP_SETPOINT every cycle of its clock (the
// Planner's pose for the wall-clock time, so a late cycle never makes the
// motion drift) and EDSP_STATUS (running, then holding the final pose).
// edsp-planner's main only parses options, builds the Planner and runs
// this; tests run it on an in-process bus with their own clock.

#include <chrono>
#include <cstdint>
#include <functional>

#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "edsp/planner/planner.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/bus.h"

namespace edsp {

// On the host's millisecond grid, phase 0: the bridge ticks a fixed phase
// after it.
inline constexpr std::chrono::microseconds kPlannerPeriod{1000};

struct PlannerLoopOptions {
  double exit_after_hold_s = -1.0;  // after the motion, hold this long and stop (< 0: until stopped)
};

class PlannerLoop {
 public:
  // Set-up: advertises on `bus` (may throw TransportError). The bus and the
  // planner must outlive the loop.
  PlannerLoop(Bus& bus, Planner& planner, PlannerLoopOptions options);
  PlannerLoop(const PlannerLoop&) = delete;
  PlannerLoop& operator=(const PlannerLoop&) = delete;

  // The motion's time zero (wall clock, microseconds).
  void Start(std::int64_t start_utime);
  // One cycle at `now`: the setpoint and, once a second, the status. False
  // once the final pose has been held for exit_after_hold_s.
  bool RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);
  // Starts now, then a cycle at each tick of `clock` until stop() is true
  // or the hold is over.
  void Run(CycleClock& clock, const std::function<bool()>& stop);

 private:
  Planner& planner_;
  PlannerLoopOptions options_;
  Bus::Publisher<pose_setpoint_t> setpoints_;
  Bus::Publisher<node_status_t> status_out_;
  NodeStatus status_{"planner"};
  std::int64_t start_utime_ = 0;
};

}  // namespace edsp
