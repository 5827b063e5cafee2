// libFuzzer: the LCM message decoders as the nodes use them. The first byte
// picks the type; the rest is the packet, whatever it is: a wrong
// fingerprint, truncated, oversized, or garbage. A packet that decodes must
// re-encode to a packet that decodes to the same bytes again (round trip).
// (lcm-gen's getEncodedSize() counts a string's embedded NUL and what
// follows it, its encoder stops there: the bytes encode wrote are the message.)
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "edsp/arm_t.hpp"
#include "edsp/fault_t.hpp"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/node_status_t.hpp"
#include "edsp/platform_config_t.hpp"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/pr_mode_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "edsp/transport/decode.h"

namespace {

// What a node re-publishing it would send: encode's own count of bytes.
template <typename Msg>
std::vector<std::uint8_t> Encoded(const Msg& msg) {
  const int capacity = msg.getEncodedSize();
  if (capacity < 0) std::abort();
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(capacity));
  const int written = msg.encode(bytes.data(), 0, capacity);
  if (written < 0 || written > capacity) std::abort();
  bytes.resize(static_cast<std::size_t>(written));
  return bytes;
}

template <typename Msg>
void DecodeAsANodeDoes(const std::uint8_t* data, std::size_t size) {
  Msg msg;
  if (!edsp::DecodeUntrusted(&msg, data, size)) return;  // refused: fine
  const std::vector<std::uint8_t> once = Encoded(msg);
  Msg again;
  if (again.decode(once.data(), 0, static_cast<int>(once.size())) != static_cast<int>(once.size())) std::abort();
  if (Encoded(again) != once) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > (1u << 20)) return 0;
  const std::uint8_t* packet = data + 1;
  const std::size_t n = size - 1;
  switch (data[0] % 11) {
    case 0: DecodeAsANodeDoes<edsp::pose_setpoint_t>(packet, n); break;
    case 1: DecodeAsANodeDoes<edsp::leg_command_t>(packet, n); break;
    case 2: DecodeAsANodeDoes<edsp::leg_state_t>(packet, n); break;
    case 3: DecodeAsANodeDoes<edsp::platform_state_t>(packet, n); break;
    case 4: DecodeAsANodeDoes<edsp::platform_config_t>(packet, n); break;
    case 5: DecodeAsANodeDoes<edsp::tracker_point_t>(packet, n); break;
    case 6: DecodeAsANodeDoes<edsp::rig_truth_t>(packet, n); break;
    case 7: DecodeAsANodeDoes<edsp::node_status_t>(packet, n); break;
    case 8: DecodeAsANodeDoes<edsp::fault_t>(packet, n); break;
    case 9: DecodeAsANodeDoes<edsp::arm_t>(packet, n); break;
    default: DecodeAsANodeDoes<edsp::pr_mode_t>(packet, n); break;
  }
  return 0;
}
