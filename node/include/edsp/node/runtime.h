#pragma once
// What every node process shares: a clean stop on SIGINT/SIGTERM, a loop on
// an absolute clock (no drift, missed cycles counted), and the status it
// reports on EDSP_STATUS at 1 Hz and on every change of state.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "edsp/node_status_t.hpp"

namespace edsp {

// SIGINT and SIGTERM set a flag instead of killing the process.
void InstallStopSignals();
bool StopRequested();

// main() of every edsp program: runs `run`, and turns an exception into
// "<program>: error: <what>" on stderr and exit code `error_exit`.
int RunMain(const char* program, int (*run)(int, char**), int argc, char** argv, int error_exit = 1);

// Microseconds since the epoch (LCM's utime).
std::int64_t UtimeNow();

// What a cyclic loop waits on: the bridge's own steady clock, or a clock a
// drive backend owns (an EtherCAT master on distributed clocks). The loop
// handles input for UntilNext(), then calls WaitNext() to start a cycle.
class CycleClock {
 public:
  virtual ~CycleClock() = default;
  virtual void WaitNext() = 0;
  // Time left until the next tick (<= 0 once it is due).
  virtual std::chrono::nanoseconds UntilNext() const = 0;
  virtual std::int64_t missed() const = 0;
  virtual std::chrono::nanoseconds period() const = 0;
};

// Ticks at a fixed period on CLOCK_MONOTONIC with absolute deadlines. A
// cycle that starts more than one period late counts as missed, and the
// clock skips ahead rather than bursting. With a phase, the ticks fall on
// the host's grid (multiples of the period since CLOCK_MONOTONIC's origin)
// plus that phase, so two loops on one host keep a fixed phase between them
// (the planner at 0, the bridge after it: a cyclic master's shift time).
class RateClock final : public CycleClock {
 public:
  explicit RateClock(std::chrono::nanoseconds period);
  RateClock(std::chrono::nanoseconds period, std::chrono::nanoseconds phase);
  void WaitNext() override;
  std::chrono::nanoseconds UntilNext() const override;
  std::int64_t missed() const override { return missed_; }
  std::chrono::nanoseconds period() const override { return period_; }

 private:
  std::chrono::nanoseconds period_;
  std::int64_t next_ns_;
  std::int64_t missed_ = 0;
};

// The first tick after `now_ns` on the grid of `period_ns` shifted by
// `phase_ns` (period > 0; any phase, taken modulo the period).
std::int64_t NextGridTick(std::int64_t now_ns, std::int64_t period_ns, std::int64_t phase_ns);

// Loop-time percentiles and message counters for EDSP_STATUS.
class NodeStatus {
 public:
  explicit NodeStatus(std::string node);
  void RecordLoop(std::chrono::nanoseconds busy);
  void CountIn(std::int64_t n = 1) { in_ += n; }
  void CountOut(std::int64_t n = 1) { out_ += n; }
  void CountRejected() { ++rejected_; }
  void SetDrops(std::int64_t drops) { drops_ = drops; }
  void SetState(std::int8_t state) { state_ = state; }
  // The message for now; resets the loop-time window.
  node_status_t Report(std::int64_t utime, std::int64_t deadline_misses);
  // True once a second, and as soon as the state differs from the last
  // report (a hold shorter than a second is seen too), at most every 10 ms
  // (the caller then publishes Report()).
  bool Due(std::int64_t utime);

 private:
  static constexpr std::int64_t kReportPeriod_us = 1000000;
  static constexpr std::int64_t kMinReportInterval_us = 10000;
  std::string node_;
  std::int8_t state_ = node_status_t::STATE_STARTING;
  std::int8_t reported_state_ = node_status_t::STATE_STARTING;
  std::int64_t last_report_utime_ = 0;
  std::int64_t in_ = 0, out_ = 0, rejected_ = 0, drops_ = 0, seq_ = 0;
  std::int64_t next_report_utime_ = 0;
  std::vector<double> loop_us_;
};

}  // namespace edsp
