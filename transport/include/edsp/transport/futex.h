#pragma once
// Process-shared futex wait/wake on a 32-bit word in shared memory: how a
// blocking shared-memory reader sleeps without burning a core.

#include <atomic>
#include <chrono>
#include <cstdint>

namespace edsp {

// Sleeps while *word == expected, at most `timeout`. Returns false on timeout.
// Spurious returns are possible; callers re-check their condition.
bool FutexWait(std::atomic<std::uint32_t>* word, std::uint32_t expected, std::chrono::nanoseconds timeout) noexcept;

// Sleeps while every words[i] == expected[i] (at most 128 words), at most
// `timeout`: one thread waiting on several shared-memory channels at once
// (futex_waitv, Linux ≥ 5.16). Returns false on timeout; spurious returns
// are possible. Where the kernel lacks futex_waitv it sleeps on words[0]
// for at most 200 µs (slices), so the other words are still seen.
bool FutexWaitAny(std::atomic<std::uint32_t>* const* words, const std::uint32_t* expected, int count,
                  std::chrono::nanoseconds timeout) noexcept;

// Wakes every waiter on *word.
void FutexWakeAll(std::atomic<std::uint32_t>* word) noexcept;

}  // namespace edsp
