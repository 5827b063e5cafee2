#pragma once
// What the launcher sees of its members beyond their exits: a member stopped
// by a signal (SIGSTOP, a debugger) is frozen, not dead, and nothing of the
// process table says so to anyone else. The launcher reports it (and its
// resumption, exits and restarts) on EDSP_FAULT, and its own EDSP_STATUS is
// STATE_FAULT while any member is frozen or down.

#include <sys/types.h>

#include <cstdint>
#include <string>

namespace edsp {

enum class ProcessState { kRunning, kStopped, kTraced, kGone };

// From /proc/<pid>/stat: 'T' stopped by a signal, 't' stopped by a tracer;
// no such process or a zombie is gone; anything else runs.
ProcessState ReadProcessState(pid_t pid);

// A tracer stop this long is a freeze (a debugger at a breakpoint); shorter
// ones are not: LeakSanitizer traces its own process at every exit.
inline constexpr std::int64_t kTracedFreezeUs = 1000000;

// One member's frozen/running transitions.
class FreezeWatch {
 public:
  enum class Change { kNone, kFroze, kResumed };
  // `now_us`: any monotonic microsecond clock. A process that exits while
  // frozen is not "resumed": Forget() it when it is reaped.
  Change Observe(ProcessState state, std::int64_t now_us);
  void Forget() { frozen_ = false; }
  bool frozen() const { return frozen_; }
  std::int64_t frozen_for_us(std::int64_t now_us) const { return frozen_ ? now_us - since_us_ : 0; }

 private:
  bool frozen_ = false;
  std::int64_t since_us_ = 0;
  std::int64_t traced_since_us_ = -1;
};

}  // namespace edsp
