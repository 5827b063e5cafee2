#include "edsp/transport/futex.h"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>

namespace edsp {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

bool FutexWait(std::atomic<std::uint32_t>* word, std::uint32_t expected, std::chrono::nanoseconds timeout) noexcept {
  const auto ns = timeout.count() > 0 ? timeout.count() : 0;
  timespec relative{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
  // Not FUTEX_PRIVATE_FLAG: the word lives in memory shared between processes.
  const long rc =
      syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(word), FUTEX_WAIT, expected, &relative, nullptr, 0);
  return !(rc == -1 && errno == ETIMEDOUT);
}

bool FutexWaitAny(std::atomic<std::uint32_t>* const* words, const std::uint32_t* expected, int count,
                  std::chrono::nanoseconds timeout) noexcept {
  if (count <= 0) return false;
  if (count > FUTEX_WAITV_MAX) count = FUTEX_WAITV_MAX;
  futex_waitv waiters[FUTEX_WAITV_MAX] = {};
  for (int i = 0; i < count; ++i) {
    waiters[i].val = expected[i];
    waiters[i].uaddr = reinterpret_cast<std::uintptr_t>(words[i]);
    waiters[i].flags = FUTEX_32;  // not FUTEX_PRIVATE_FLAG: shared between processes
  }
  // futex_waitv takes an absolute deadline on the clock it is given.
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  const auto ns = (timeout.count() > 0 ? timeout.count() : 0) + now.tv_nsec;
  timespec deadline{now.tv_sec + static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
  const long rc = syscall(SYS_futex_waitv, waiters, static_cast<unsigned>(count), 0u, &deadline, CLOCK_MONOTONIC);
  if (rc == -1 && errno == ENOSYS) {
    return FutexWait(words[0], expected[0],
                     std::min<std::chrono::nanoseconds>(timeout, std::chrono::microseconds(200)));
  }
  return !(rc == -1 && errno == ETIMEDOUT);
}

void FutexWakeAll(std::atomic<std::uint32_t>* word) noexcept {
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(word), FUTEX_WAKE, INT_MAX, nullptr, nullptr, 0);
}

}  // namespace edsp
