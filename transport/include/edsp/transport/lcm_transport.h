#pragma once
// The one place edsp touches lcm::LCM: construction checked with good(), raw
// byte publish/subscribe, and handlers that may throw (the exception is kept
// and rethrown from Handle, never propagated through LCM's C code).

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace edsp {

// Host-only multicast: nothing leaves the machine unless a group file says so.
// A 4 MiB receive buffer rides out scheduling stalls of a loaded host (the
// logger takes every channel at several kHz); the kernel caps it at
// net.core.rmem_max, which `deploy/edsp` raises to match.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

class LcmTransport {
 public:
  using RawHandler = std::function<void(const std::string& channel, const std::uint8_t* data, std::uint32_t size)>;

  // Throws TransportError naming the URL if LCM cannot be initialised.
  explicit LcmTransport(const std::string& url = kDefaultLcmUrl);
  ~LcmTransport();
  LcmTransport(const LcmTransport&) = delete;
  LcmTransport& operator=(const LcmTransport&) = delete;

  // Returns false (and counts it) if LCM refused the message.
  bool Publish(const std::string& channel, const void* data, std::uint32_t size) noexcept;

  // `channel` is matched exactly (regex metacharacters are escaped).
  void Subscribe(const std::string& channel, RawHandler handler);
  // For tools that want many channels (the logger): a POSIX extended regex.
  void SubscribePattern(const std::string& regex, RawHandler handler);

  // Waits up to `timeout` for traffic, then dispatches everything pending.
  // Returns the number of messages dispatched. Rethrows the first exception
  // a handler threw.
  int Handle(std::chrono::microseconds timeout);

  int fileno() const;
  // A message is waiting (poll with no wait).
  bool Readable() const;
  std::size_t subscription_count() const { return subscriptions_.size(); }
  const std::string& url() const { return url_; }
  std::uint64_t publish_failures() const { return publish_failures_; }

 private:
  struct Subscription;
  void Dispatch(const lcm::ReceiveBuffer* buffer, const std::string& channel, RawHandler* handler);
  int DrainReady();

  std::string url_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  std::exception_ptr pending_error_;
  int dispatched_ = 0;
  std::uint64_t publish_failures_ = 0;
};

// Escapes POSIX regex metacharacters so a channel name matches only itself.
std::string EscapeChannelRegex(const std::string& channel);

}  // namespace edsp
