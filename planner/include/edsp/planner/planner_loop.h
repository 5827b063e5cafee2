#pragma once
// The planner on a bus: EDSP_SETPOINT every cycle of its clock (the motion
// service's pose for the wall-clock time, so a late cycle never makes a
// motion drift), EDSP_MOTION_REPLY to each EDSP_MOTION_REQUEST,
// EDSP_MOTION_STATUS at 50 Hz and at once on a change, and EDSP_STATUS.
// It listens to EDSP_LEG_STATE (is the bridge following?) and
// EDSP_PLATFORM_STATE (the measured pose). edsp-planner's main only parses
// options, builds the service and runs this; tests run it on an in-process
// bus with their own clock. Moves, checks and runs are planned on a worker
// thread, not real-time (a long program's check takes tens of milliseconds,
// and the setpoints must not wait: scheduling.h); halt, stop and the rest are answered on the
// loop's thread at once. Every reply goes out at the next cycle, in the
// order the requests were acted on; a request's age is taken when it came.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/planner/motion_service.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/timing_contract.h"
#include "edsp/transport/bus.h"

namespace edsp {

// On the host's millisecond grid, phase 0: the bridge ticks a fixed phase
// after it.
inline constexpr std::chrono::microseconds kPlannerPeriod{timing::kCycleUs};

struct PlannerLoopOptions {
  double exit_after_hold_s = -1.0;  // after the launch program, hold this long and stop (< 0: until stopped)
  double status_rate_hz = 50.0;     // EDSP_MOTION_STATUS
};

class PlannerLoop {
 public:
  // Set-up: advertises and subscribes on `bus` (may throw TransportError).
  // The bus and the service must outlive the loop.
  PlannerLoop(Bus& bus, MotionService& service, PlannerLoopOptions options);
  ~PlannerLoop();
  PlannerLoop(const PlannerLoop&) = delete;
  PlannerLoop& operator=(const PlannerLoop&) = delete;

  // One cycle at `now`: the setpoint, the motion status when due, and once
  // a second the node status. False once the launch program's final pose
  // has been held for exit_after_hold_s.
  bool RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);
  // A cycle at each tick of `clock`, handling requests between ticks,
  // until stop() is true or the hold is over.
  void Run(CycleClock& clock, const std::function<bool()>& stop);

 private:
  void OnRequest(const motion_request_t& request);
  void PlanRequests();  // the worker
  void PublishReplies();

  Bus& bus_;
  MotionService& service_;
  PlannerLoopOptions options_;
  Bus::Publisher<pose_setpoint_t> setpoints_;
  Bus::Publisher<motion_reply_t> replies_;
  Bus::Publisher<motion_status_t> motion_status_;
  NodeReporting reporting_;
  std::int64_t next_motion_status_utime_ = 0;
  std::int64_t motion_status_seq_ = 0;  // the publisher's own count: a reader's seq gaps are losses

  std::mutex mutex_;  // guards the two queues and quit_
  std::condition_variable wake_;
  std::deque<std::pair<motion_request_t, std::int64_t>> to_plan_;  // with the utime it came
  std::deque<motion_reply_t> replies_out_;
  bool quit_ = false;
  std::thread worker_;
};

}  // namespace edsp
