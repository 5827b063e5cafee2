#include "edsp/node/scheduling.h"

#include <pthread.h>
#include <sched.h>

namespace edsp {

bool LeaveRealTime() {
  int policy = SCHED_OTHER;
  sched_param param{};
  if (pthread_getschedparam(pthread_self(), &policy, &param) != 0) return false;
  if (policy != SCHED_FIFO && policy != SCHED_RR) return true;
  param.sched_priority = 0;
  return pthread_setschedparam(pthread_self(), SCHED_OTHER, &param) == 0;
}

}  // namespace edsp
