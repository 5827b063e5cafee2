// Ping-pong over LCM udpm (the caller runs it inside a private network namespace).
#include <cstring>

#include "edsp/transport/lcm_transport.h"
#include "endpoint.h"

namespace edsp::bench {
namespace {

class LcmEndpoint final : public Endpoint {
 public:
  explicit LcmEndpoint(const Roles& roles) : send_channel_(roles.send_channel) {
    lcm_.Subscribe(roles.receive_channel, [this](const std::string&, const std::uint8_t* data, std::uint32_t size) {
      if (out_ != nullptr) std::memcpy(out_, data, size < capacity_ ? size : capacity_);
      ++received_;
    });
  }

  bool Send(const std::uint8_t* data, std::uint32_t size) override { return lcm_.Publish(send_channel_, data, size); }

  bool Receive(std::uint8_t* out, std::uint32_t capacity, std::chrono::milliseconds timeout) override {
    out_ = out;
    capacity_ = capacity;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    const std::uint64_t before = received_;
    while (received_ == before) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return false;
      lcm_.Handle(std::chrono::duration_cast<std::chrono::microseconds>(deadline - now));
    }
    return true;
  }

 private:
  LcmTransport lcm_;
  std::string send_channel_;
  std::uint8_t* out_ = nullptr;
  std::uint32_t capacity_ = 0;
  std::uint64_t received_ = 0;
};

}  // namespace

std::unique_ptr<Endpoint> MakeLcmEndpoint(const Roles& roles) { return std::make_unique<LcmEndpoint>(roles); }

}  // namespace edsp::bench
