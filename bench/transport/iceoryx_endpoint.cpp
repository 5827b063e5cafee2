// Ping-pong over Eclipse iceoryx (Debian's 2.0.3): untyped publisher and
// subscriber, polling take() or sleeping in a WaitSet. RouDi must be running.
#include <cstring>
#include <stdexcept>
#include <thread>

#include "endpoint.h"
#include "iceoryx_posh/popo/untyped_publisher.hpp"
#include "iceoryx_posh/popo/untyped_subscriber.hpp"
#include "iceoryx_posh/popo/wait_set.hpp"
#include "iceoryx_hoofs/log/logmanager.hpp"
#include "iceoryx_posh/runtime/posh_runtime.hpp"

namespace edsp::bench {
namespace {

iox::capro::IdString_t Id(const std::string& text) {
  return iox::capro::IdString_t(iox::cxx::TruncateToCapacity, text.c_str(), text.size());
}

class IceoryxEndpoint final : public Endpoint {
 public:
  IceoryxEndpoint(const Roles& roles, bool waitset)
      : publisher_({Id("edsp"), Id(roles.run_id), Id(roles.send_channel)}),
        subscriber_({Id("edsp"), Id(roles.run_id), Id(roles.receive_channel)}, SubscriberOptions()) {
    if (waitset) {
      waitset_ = std::make_unique<iox::popo::WaitSet<>>();
      waitset_->attachState(subscriber_, iox::popo::SubscriberState::HAS_DATA).or_else([](auto) {
        throw std::runtime_error("iceoryx: cannot attach the subscriber to a WaitSet");
      });
    }
  }

  ~IceoryxEndpoint() override {
    if (waitset_) waitset_->detachState(subscriber_, iox::popo::SubscriberState::HAS_DATA);
  }

  void WaitForPeer() override {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while ((!publisher_.hasSubscribers() || subscriber_.getSubscriptionState() != iox::SubscribeState::SUBSCRIBED) &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }

  bool Send(const std::uint8_t* data, std::uint32_t size) override {
    bool sent = false;
    publisher_.loan(size).and_then([&](void* payload) {
      std::memcpy(payload, data, size);
      publisher_.publish(payload);
      sent = true;
    });
    return sent;
  }

  bool Receive(std::uint8_t* out, std::uint32_t capacity, std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      bool got = false;
      subscriber_.take().and_then([&](const void* payload) {
        const auto* header = iox::mepoo::ChunkHeader::fromUserPayload(payload);
        const std::uint32_t size = header->userPayloadSize();
        std::memcpy(out, payload, size < capacity ? size : capacity);
        subscriber_.release(payload);
        got = true;
      });
      if (got) return true;
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return false;
      if (waitset_) {
        waitset_->timedWait(iox::units::Duration::fromMilliseconds(
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count() + 1));
      }
    }
  }

 private:
  static iox::popo::SubscriberOptions SubscriberOptions() {
    iox::popo::SubscriberOptions options;
    options.queueCapacity = 16;
    return options;
  }

  iox::popo::UntypedPublisher publisher_;
  iox::popo::UntypedSubscriber subscriber_;
  std::unique_ptr<iox::popo::WaitSet<>> waitset_;
};

}  // namespace

std::unique_ptr<Endpoint> MakeIceoryxEndpoint(const Roles& roles, std::uint32_t /*payload_bytes*/, bool waitset) {
  // iceoryx logs every registration at debug level by default.
  iox::log::LogManager::GetLogManager().SetDefaultLogLevel(iox::log::LogLevel::kWarn);
  const std::string name = "edsp-bench-" + roles.send_channel + "-" + std::to_string(::getpid());
  iox::runtime::PoshRuntime::initRuntime(iox::RuntimeName_t(iox::cxx::TruncateToCapacity, name.c_str(), name.size()));
  return std::make_unique<IceoryxEndpoint>(roles, waitset);
}

}  // namespace edsp::bench
