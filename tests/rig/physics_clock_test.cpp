// The rig emulator's physics clock: whole cycles, the missed ones caught up,
// anchored to the earliest wake, a freeze not replayed.
#include "edsp/rig/physics_clock.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace edsp {
namespace {

constexpr std::int64_t kT0 = 1'000'000;

// Runs the wake's cycles as RigCycle does; returns their instants.
std::vector<std::int64_t> Wake(PhysicsClock* clock, std::int64_t now) {
  std::vector<std::int64_t> at;
  const int cycles = clock->CyclesFor(now);
  for (int k = 0; k < cycles; ++k) {
    at.push_back(clock->at());
    clock->Advance();
  }
  return at;
}

TEST(PhysicsClock, OnTimeWakesRunOneCycleEachOnTheFirstWakesGrid) {
  PhysicsClock clock(1000, 50);
  EXPECT_EQ(Wake(&clock, kT0), std::vector<std::int64_t>{kT0});
  // Woken up to a cycle late: one cycle each, stamped on the grid.
  for (int k = 1; k < 100; ++k) {
    const std::int64_t jitter = (k * 37) % 900;
    EXPECT_EQ(Wake(&clock, kT0 + 1000 * k + jitter), std::vector<std::int64_t>{kT0 + 1000 * k}) << k;
  }
}

TEST(PhysicsClock, ALateWakeRunsTheCyclesItMissedEachAtItsInstant) {
  PhysicsClock clock(1000, 50);
  Wake(&clock, kT0);
  // The next wake should have come at +1 ms; it came 2.3 cycles after that.
  const std::vector<std::int64_t> expected{kT0 + 1000, kT0 + 2000, kT0 + 3000};
  EXPECT_EQ(Wake(&clock, kT0 + 3300), expected);
  EXPECT_EQ(Wake(&clock, kT0 + 4050), std::vector<std::int64_t>{kT0 + 4000});
  EXPECT_EQ(clock.freezes(), 0);
}

TEST(PhysicsClock, AnEarlierWakeMovesTheClockToIt) {
  PhysicsClock clock(1000, 50);
  Wake(&clock, kT0 + 800);  // a slow first wake
  EXPECT_EQ(Wake(&clock, kT0 + 1020), std::vector<std::int64_t>{kT0 + 1020});
  // From then on the grid is the earlier wake's: a wake 900 µs late is on time.
  EXPECT_EQ(Wake(&clock, kT0 + 2920), std::vector<std::int64_t>{kT0 + 2020});
}

TEST(PhysicsClock, AWakeLaterThanTheLongestCatchUpIsAFreezeNotReplayed) {
  PhysicsClock clock(1000, 50);
  Wake(&clock, kT0);
  EXPECT_EQ(Wake(&clock, kT0 + 1000 + 50'000).size(), 51u);  // the longest catch-up and its own
  EXPECT_EQ(clock.freezes(), 0);
  const std::int64_t frozen = kT0 + 52'000 + 51'000;
  EXPECT_EQ(Wake(&clock, frozen), std::vector<std::int64_t>{frozen});
  EXPECT_EQ(clock.freezes(), 1);
}

TEST(PhysicsClock, AnAbsurdCycleIsRefused) {
  EXPECT_THROW(PhysicsClock(0, 50), std::invalid_argument);
  EXPECT_THROW(PhysicsClock(1000, -1), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
