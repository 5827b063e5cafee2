#pragma once
// A CycleClock for tests of a node's Run: ticks `ticks` times at once, never
// waits, and reports `missed` cycles, so a test owns the loop's time.
#include <chrono>
#include <cstdint>

#include "edsp/node/runtime.h"

namespace edsp::test_support {

class CountingClock final : public CycleClock {
 public:
  explicit CountingClock(int ticks, std::int64_t missed = 0) : left_(ticks), missed_(missed) {}
  void WaitNext() override { --left_; }
  std::chrono::nanoseconds UntilNext() const override { return std::chrono::nanoseconds(0); }
  std::int64_t missed() const override { return missed_; }
  std::chrono::nanoseconds period() const override { return std::chrono::milliseconds(1); }
  // The loop is due no more: every tick has been taken.
  bool done() const { return left_ <= 0; }

 private:
  int left_;
  std::int64_t missed_;
};

}  // namespace edsp::test_support
