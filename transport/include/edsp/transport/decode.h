#pragma once
// Decoding a packet that came from outside (a socket, a shared-memory slot,
// a log file). lcm-gen's decoders trusted a string's length field: a zero
// one made std::string::assign throw std::length_error, which came out of
// Bus::Handle and stopped the node (found by fuzz_lcm_decode: one crafted
// packet on EDSP_SETPOINT). The build now rejects lengths below 1 in the
// generated code (lcmtypes/CMakeLists.txt); whatever else a decoder throws
// (std::bad_alloc) is a bad packet here too, never a crash.

#include <climits>
#include <cstddef>

namespace edsp {

// True if `data` holds a valid Msg (decoded into *msg).
template <typename Msg>
bool DecodeUntrusted(Msg* msg, const void* data, std::size_t size) noexcept {
  if (size > static_cast<std::size_t>(INT_MAX)) return false;
  try {
    return msg->decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (...) {
    return false;
  }
}

}  // namespace edsp
