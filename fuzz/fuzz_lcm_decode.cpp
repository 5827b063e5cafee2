// libFuzzer: the LCM message decoders as the nodes use them. The first byte
// picks the type (its index in message_types.h, modulo their count); the rest is the packet, whatever it is: a wrong
// fingerprint, truncated, oversized, or garbage. A packet that decodes must
// re-encode to a packet that decodes to the same bytes again (round trip).
// (lcm-gen's getEncodedSize() counts a string's embedded NUL and what
// follows it, its encoder stops there: the bytes encode wrote are the message.)
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "edsp/message_types.h"
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
  edsp::VisitMessageType(data[0] % edsp::kMessageTypeCount,
                         [&](auto tag) { DecodeAsANodeDoes<typename decltype(tag)::type>(packet, n); });
  return 0;
}
