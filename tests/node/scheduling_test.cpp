// A thread that leaves real-time scheduling is normal afterwards, and one
// that never was stays as it is.
#include "edsp/node/scheduling.h"

#include <pthread.h>
#include <sched.h>

#include <gtest/gtest.h>

#include <thread>

namespace edsp {
namespace {

int PolicyOfThisThread() {
  int policy = -1;
  sched_param param{};
  pthread_getschedparam(pthread_self(), &policy, &param);
  return policy;
}

TEST(LeaveRealTime, AThreadStartedByARealTimeOneBecomesNormal) {
  int inherited = -1, after = -1;
  bool left = false;
  std::thread([&] {
    sched_param param{};
    param.sched_priority = 10;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0) return;
    // A worker started here inherits SCHED_FIFO, as a node's do.
    std::thread([&] {
      inherited = PolicyOfThisThread();
      left = LeaveRealTime();
      after = PolicyOfThisThread();
    }).join();
  }).join();
  if (inherited == -1) GTEST_SKIP() << "SCHED_FIFO refused here (needs root or CAP_SYS_NICE)";
  EXPECT_EQ(inherited, SCHED_FIFO);
  EXPECT_TRUE(left);
  EXPECT_EQ(after, SCHED_OTHER);
}

TEST(LeaveRealTime, AThreadThatIsNotRealTimeKeepsItsPolicy) {
  int before = -1, after = -1;
  bool left = false;
  std::thread([&] {
    before = PolicyOfThisThread();  // the test's own: SCHED_OTHER, or BATCH/IDLE under a background run
    left = LeaveRealTime();
    after = PolicyOfThisThread();
  }).join();
  ASSERT_NE(before, SCHED_FIFO);
  ASSERT_NE(before, SCHED_RR);
  EXPECT_TRUE(left);
  EXPECT_EQ(after, before);
}

}  // namespace
}  // namespace edsp
