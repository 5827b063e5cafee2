// The launcher's view of a member beyond its exit: stopped (frozen) and
// running again, read from the process table of a real child.
#include "member_watch.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace edsp {
namespace {

ProcessState WaitFor(pid_t pid, ProcessState wanted) {
  ProcessState state = ReadProcessState(pid);
  for (int k = 0; k < 200 && state != wanted; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    state = ReadProcessState(pid);
  }
  return state;
}

TEST(MemberWatch, AStoppedChildIsFrozenUntilContinuedAndGoneOnceReaped) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    for (;;) ::pause();
  }
  FreezeWatch watch;
  EXPECT_EQ(WaitFor(child, ProcessState::kRunning), ProcessState::kRunning);
  EXPECT_EQ(watch.Observe(ProcessState::kRunning, 0), FreezeWatch::Change::kNone);
  ::kill(child, SIGSTOP);
  EXPECT_EQ(WaitFor(child, ProcessState::kStopped), ProcessState::kStopped);
  EXPECT_EQ(watch.Observe(ProcessState::kStopped, 1000), FreezeWatch::Change::kFroze);
  EXPECT_EQ(watch.Observe(ProcessState::kStopped, 2000), FreezeWatch::Change::kNone);  // once
  EXPECT_TRUE(watch.frozen());
  EXPECT_EQ(watch.frozen_for_us(501000), 500000);
  ::kill(child, SIGCONT);
  EXPECT_EQ(WaitFor(child, ProcessState::kRunning), ProcessState::kRunning);
  EXPECT_EQ(watch.Observe(ProcessState::kRunning, 600000), FreezeWatch::Change::kResumed);
  EXPECT_FALSE(watch.frozen());
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_EQ(ReadProcessState(child), ProcessState::kGone);
}

// LeakSanitizer traces its own process at exit (state 't' for a moment):
// not a freeze. A tracer holding it for a second (a debugger) is one.
TEST(MemberWatch, OnlyALongTracerStopIsAFreeze) {
  FreezeWatch watch;
  EXPECT_EQ(watch.Observe(ProcessState::kTraced, 0), FreezeWatch::Change::kNone);
  EXPECT_EQ(watch.Observe(ProcessState::kTraced, kTracedFreezeUs / 2), FreezeWatch::Change::kNone);
  EXPECT_EQ(watch.Observe(ProcessState::kRunning, kTracedFreezeUs / 2 + 10), FreezeWatch::Change::kNone);
  EXPECT_EQ(watch.Observe(ProcessState::kTraced, 2 * kTracedFreezeUs), FreezeWatch::Change::kNone);
  EXPECT_EQ(watch.Observe(ProcessState::kTraced, 3 * kTracedFreezeUs), FreezeWatch::Change::kFroze);
  EXPECT_EQ(watch.Observe(ProcessState::kRunning, 3 * kTracedFreezeUs + 10), FreezeWatch::Change::kResumed);
}

TEST(MemberWatch, AProcessThatExitsWhileFrozenIsNotResumed) {
  FreezeWatch watch;
  EXPECT_EQ(watch.Observe(ProcessState::kStopped, 0), FreezeWatch::Change::kFroze);
  watch.Forget();  // reaped: killed while stopped
  EXPECT_FALSE(watch.frozen());
  EXPECT_EQ(watch.Observe(ProcessState::kRunning, 10), FreezeWatch::Change::kNone);
}

}  // namespace
}  // namespace edsp
