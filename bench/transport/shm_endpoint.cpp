// Ping-pong over edsp's shared-memory channels: spin on TryTake, or block
// (futex, no spinning at all: the pure blocking cost).
#include <cstring>
#include <stdexcept>
#include <thread>

#include "edsp/transport/shm_channel.h"
#include "endpoint.h"

namespace edsp::bench {
namespace {

class ShmEndpoint final : public Endpoint {
 public:
  ShmEndpoint(const Roles& roles, std::uint32_t payload_bytes, ShmWait wait) : wait_(wait) {
    ShmChannelSpec out{roles.run_id + "." + roles.send_channel, 0x6564737062656e63, 16, payload_bytes, 0600};
    auto writer = ShmWriter::Open(out);
    if (!writer.ok()) throw std::runtime_error(writer.message);
    writer_ = std::move(writer.value);
    ShmChannelSpec in = out;
    in.segment_name = roles.run_id + "." + roles.receive_channel;
    for (int attempt = 0; attempt < 5000 && reader_ == nullptr; ++attempt) {
      auto reader = ShmReader::Open(in);
      if (reader.ok()) {
        reader_ = std::move(reader.value);
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    }
    if (reader_ == nullptr) throw std::runtime_error("peer segment never appeared: " + in.segment_name);
  }

  bool Send(const std::uint8_t* data, std::uint32_t size) override {
    return writer_->Publish([&](std::uint8_t* buffer, std::uint32_t capacity) -> std::int64_t {
      if (size > capacity) return -1;
      std::memcpy(buffer, data, size);
      return size;
    }) != 0;
  }

  bool Receive(std::uint8_t* out, std::uint32_t capacity, std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const TakeStatus status = reader_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
        std::memcpy(out, data, size < capacity ? size : capacity);
        return true;
      });
      if (status == TakeStatus::kMessage) return true;
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return false;
      if (wait_ == ShmWait::kBlock) reader_->Wait(deadline - now, std::chrono::nanoseconds(0));
      if (wait_ == ShmWait::kHybrid) reader_->Wait(deadline - now);  // default spin, then futex
    }
  }

 private:
  ShmWait wait_;
  std::unique_ptr<ShmWriter> writer_;
  std::unique_ptr<ShmReader> reader_;
};

}  // namespace

std::unique_ptr<Endpoint> MakeShmEndpoint(const Roles& roles, std::uint32_t payload_bytes, ShmWait wait) {
  return std::make_unique<ShmEndpoint>(roles, payload_bytes, wait);
}

}  // namespace edsp::bench
