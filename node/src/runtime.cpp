#include "edsp/node/runtime.h"

#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <cerrno>

namespace edsp {

namespace {

std::atomic<bool> g_stop{false};

extern "C" void OnStopSignal(int) { g_stop.store(true); }

std::int64_t MonotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

}  // namespace

void InstallStopSignals() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool StopRequested() { return g_stop.load(); }

int RunMain(const char* program, int (*run)(int, char**), int argc, char** argv, int error_exit) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return error_exit;
  }
}

std::int64_t UtimeNow() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1000000 + ts.tv_nsec / 1000;
}

RateClock::RateClock(std::chrono::nanoseconds period) : period_(period), next_ns_(MonotonicNs() + period.count()) {}

RateClock::RateClock(std::chrono::nanoseconds period, std::chrono::nanoseconds phase)
    : period_(period), next_ns_(NextGridTick(MonotonicNs(), period.count(), phase.count())) {}

std::int64_t NextGridTick(std::int64_t now_ns, std::int64_t period_ns, std::int64_t phase_ns) {
  const std::int64_t shift = ((phase_ns % period_ns) + period_ns) % period_ns;
  const std::int64_t base = now_ns - shift;
  return (base / period_ns + 1) * period_ns + shift;
}

void RateClock::WaitNext() {
  timespec deadline{static_cast<time_t>(next_ns_ / 1000000000), static_cast<long>(next_ns_ % 1000000000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR && !StopRequested()) {
  }
  next_ns_ += period_.count();
  const std::int64_t now = MonotonicNs();
  if (now > next_ns_) {  // this cycle already overran the next deadline
    const std::int64_t late = (now - next_ns_) / period_.count() + 1;
    missed_ += late;
    next_ns_ += late * period_.count();
  }
}

std::chrono::nanoseconds RateClock::UntilNext() const { return std::chrono::nanoseconds(next_ns_ - MonotonicNs()); }

NodeStatus::NodeStatus(std::string node) : node_(std::move(node)) { loop_us_.reserve(4096); }

void NodeStatus::RecordLoop(std::chrono::nanoseconds busy) {
  if (loop_us_.size() < loop_us_.capacity()) {
    loop_us_.push_back(static_cast<double>(busy.count()) * 1e-3);
  }
}

bool NodeStatus::Due(std::int64_t utime) {
  const bool periodic = utime >= next_report_utime_;
  const bool changed = state_ != reported_state_ && utime >= last_report_utime_ + kMinReportInterval_us;
  if (!periodic && !changed) return false;
  if (periodic) next_report_utime_ = utime + kReportPeriod_us;
  last_report_utime_ = utime;
  return true;
}

node_status_t NodeStatus::Report(std::int64_t utime, std::int64_t deadline_misses) {
  node_status_t s{};
  s.utime = utime;
  s.seq = ++seq_;
  s.node = node_;
  s.pid = static_cast<std::int32_t>(::getpid());
  s.state = state_;
  reported_state_ = state_;
  s.messages_in = in_;
  s.messages_out = out_;
  s.drops = drops_;
  s.rejected = rejected_;
  s.deadline_misses = deadline_misses;
  if (!loop_us_.empty()) {
    std::sort(loop_us_.begin(), loop_us_.end());
    auto at = [&](double q) {
      return loop_us_[std::min(loop_us_.size() - 1,
                               static_cast<std::size_t>(q * static_cast<double>(loop_us_.size())))];
    };
    s.loop_p50_us = at(0.5);
    s.loop_p99_us = at(0.99);
    s.loop_max_us = loop_us_.back();
    loop_us_.clear();
  }
  return s;
}

}  // namespace edsp
