#pragma once
// A message's LCM bytes, as a node would send them.

#include <cstdint>
#include <vector>

namespace edsp::test_support {

template <typename Msg>
std::vector<std::uint8_t> Encoded(const Msg& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace edsp::test_support
