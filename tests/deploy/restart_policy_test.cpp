// The launcher's decision when a member exits, against the written rules:
// restart by policy and budget with a doubling backoff, a clean exit of the
// --until-exit member ends the run, a member down for good stops the group.
#include "restart_policy.h"

#include <gtest/gtest.h>

namespace edsp {
namespace {

MemberSpec Member(RestartPolicy policy, int max_restarts = 10) {
  MemberSpec m;
  m.name = "rig";
  m.restart = policy;
  m.max_restarts = max_restarts;
  return m;
}

TEST(RestartPolicy, BackoffDoublesFrom100msAndStopsAt5s) {
  const int expected[] = {100, 200, 400, 800, 1600, 3200, 5000, 5000, 5000};
  for (int n = 0; n < 9; ++n) EXPECT_EQ(RestartBackoffMs(n), expected[n]) << n << " restarts made";
}

TEST(RestartPolicy, OnFailureRestartsAFailureAndLetsACleanExitBe) {
  const ExitDecision crash = DecideOnExit(Member(RestartPolicy::kOnFailure), 2, true, false, false);
  EXPECT_TRUE(crash.restart);
  EXPECT_EQ(crash.backoff_ms, 400);
  EXPECT_FALSE(crash.stop_group);
  EXPECT_FALSE(crash.failed_for_good);

  const ExitDecision clean = DecideOnExit(Member(RestartPolicy::kOnFailure), 0, false, false, false);
  EXPECT_FALSE(clean.restart);
  EXPECT_FALSE(clean.stop_group) << "a member that finished its work does not stop the others";
  EXPECT_FALSE(clean.failed_for_good);
}

TEST(RestartPolicy, AlwaysRestartsEvenACleanExit) {
  const ExitDecision d = DecideOnExit(Member(RestartPolicy::kAlways), 0, false, false, false);
  EXPECT_TRUE(d.restart);
  EXPECT_EQ(d.backoff_ms, 100);
}

TEST(RestartPolicy, AFailureBeyondTheBudgetOrWithNeverIsForGoodAndStopsTheGroup) {
  for (const ExitDecision& d : {DecideOnExit(Member(RestartPolicy::kOnFailure, 3), 3, true, false, false),
                                DecideOnExit(Member(RestartPolicy::kNever), 0, true, false, false)}) {
    EXPECT_FALSE(d.restart);
    EXPECT_TRUE(d.failed_for_good);
    EXPECT_TRUE(d.stop_group);
  }
}

TEST(RestartPolicy, TheUntilExitMembersCleanExitEndsTheRunWithoutARestart) {
  const ExitDecision d = DecideOnExit(Member(RestartPolicy::kAlways), 0, false, true, false);
  EXPECT_FALSE(d.restart);
  EXPECT_TRUE(d.stop_group);
  EXPECT_FALSE(d.failed_for_good);
  // Its failure is a failure like any other member's: restarted by policy.
  EXPECT_TRUE(DecideOnExit(Member(RestartPolicy::kOnFailure), 0, true, true, false).restart);
}

TEST(RestartPolicy, NothingRestartsWhileTheGroupStops) {
  const ExitDecision crash = DecideOnExit(Member(RestartPolicy::kAlways), 0, true, false, true);
  EXPECT_FALSE(crash.restart);
  EXPECT_TRUE(crash.stop_group);
  EXPECT_TRUE(crash.failed_for_good);
  const ExitDecision clean = DecideOnExit(Member(RestartPolicy::kAlways), 0, false, false, true);
  EXPECT_FALSE(clean.restart);
  EXPECT_FALSE(clean.failed_for_good);
}

}  // namespace
}  // namespace edsp
