#pragma once
// Process-shared futex wait/wake on a 32-bit word in shared memory: how a
// blocking shared-memory reader sleeps without burning a core.

#include <atomic>
#include <chrono>
#include <cstdint>

namespace edsp {

// Sleeps while *word == expected, at most `timeout`. Returns false on timeout.
// Spurious returns are possible; callers re-check their condition.
bool FutexWait(std::atomic<std::uint32_t>* word, std::uint32_t expected,
               std::chrono::nanoseconds timeout) noexcept;

// Wakes every waiter on *word.
void FutexWakeAll(std::atomic<std::uint32_t>* word) noexcept;

}  // namespace edsp
