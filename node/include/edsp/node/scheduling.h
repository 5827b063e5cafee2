#pragma once
// A node's threads and the real-time priority its launcher gave the process
// (a group file's realtime_priority and cpus). A thread the node starts
// inherits that priority and those CPUs. Work beside the cycle (a motion's
// whole-path check: tens of milliseconds) must not keep them: under
// SCHED_FIFO a thread of equal priority is never preempted, so the cycle
// would wait on the same CPU until the work was done.

namespace edsp {

// The calling thread leaves real-time scheduling for the normal policy
// (SCHED_OTHER, nice 0), on the CPUs it has: the node's real-time threads
// preempt it whenever they wake. Nothing to do for a thread that is not
// real-time. False if the kernel refused (lowering needs no privilege).
bool LeaveRealTime();

}  // namespace edsp
