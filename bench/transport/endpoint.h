#pragma once
// One side of a two-process ping-pong: send a payload, receive the peer's.
// Implementations copy the payload in and out (what a real node does when it
// encodes and decodes), so every transport pays for touching its bytes.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace edsp::bench {

class Endpoint {
 public:
  virtual ~Endpoint() = default;
  virtual bool Send(const std::uint8_t* data, std::uint32_t size) = 0;
  // Copies the next message into `out` (capacity `capacity`); false on timeout.
  virtual bool Receive(std::uint8_t* out, std::uint32_t capacity, std::chrono::milliseconds timeout) = 0;
  // Blocks until the peer is connected (publishers see a subscriber).
  virtual void WaitForPeer() {}
};

// Which channel this side writes and which it reads.
struct Roles {
  std::string send_channel;
  std::string receive_channel;
  std::string run_id;  // unique per run: segment and service names
};

// How a shared-memory reader waits: spin on TryTake, sleep on the futex at
// once, or edsp's default (spin briefly, then sleep).
enum class ShmWait { kSpin, kBlock, kHybrid };
std::unique_ptr<Endpoint> MakeShmEndpoint(const Roles& roles, std::uint32_t payload_bytes, ShmWait wait);
std::unique_ptr<Endpoint> MakeLcmEndpoint(const Roles& roles);
std::unique_ptr<Endpoint> MakeIceoryxEndpoint(const Roles& roles, std::uint32_t payload_bytes, bool waitset);

}  // namespace edsp::bench
