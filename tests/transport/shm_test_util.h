#pragma once
// Helpers for shared-memory tests: unique segment names, a self-checking
// payload, and child processes.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "edsp/transport/shm_channel.h"

namespace edsp::test_support {

inline std::string UniqueSegmentName(const std::string& what) {
  return "edsp.test." + what + "." + std::to_string(::getpid());
}

inline ShmChannelSpec TestSpec(const std::string& what, std::uint32_t slots = 8, std::uint32_t slot_size = 256) {
  ShmChannelSpec spec;
  spec.segment_name = UniqueSegmentName(what);
  spec.type_fingerprint = 0x1234'5678'9abc'def0;
  spec.slot_count = slots;
  spec.slot_size_bytes = slot_size;
  return spec;
}

// Payload: [u64 number][u32 writer tag][bytes = f(number)], self-checking so
// a torn copy cannot pass for a whole message.
inline std::int32_t EncodePattern(std::uint8_t* buffer, std::uint32_t capacity, std::uint64_t number, std::uint32_t tag,
                                  std::uint32_t size) {
  if (size > capacity || size < 16) return -1;
  std::memcpy(buffer, &number, 8);
  std::memcpy(buffer + 8, &tag, 4);
  for (std::uint32_t i = 12; i < size; ++i) {
    buffer[i] = static_cast<std::uint8_t>((number * 131u + i * 7u) & 0xff);
  }
  return static_cast<std::int32_t>(size);
}

struct Decoded {
  std::uint64_t number = 0;
  std::uint32_t tag = 0;
  bool intact = false;
};

inline bool DecodePattern(const std::uint8_t* data, std::uint32_t size, Decoded* out) {
  if (size < 16) return false;
  std::memcpy(&out->number, data, 8);
  std::memcpy(&out->tag, data + 8, 4);
  out->intact = true;
  for (std::uint32_t i = 12; i < size; ++i) {
    if (data[i] != static_cast<std::uint8_t>((out->number * 131u + i * 7u) & 0xff)) {
      out->intact = false;
      break;
    }
  }
  return out->intact;
}

// Runs `body` in a forked child that exits with its return value.
template <typename Body>
pid_t Spawn(Body&& body) {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(body());
  return pid;
}

inline int WaitExit(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace edsp::test_support
