#include "edsp/transport/lcm_transport.h"

#include <poll.h>

#include <fmt/format.h>

#include "edsp/transport/error.h"

namespace edsp {

struct LcmTransport::Subscription {
  LcmTransport* owner;
  RawHandler handler;
  // A plain function with a context, not LCM's member-function subscribe:
  // GCC 12's UBSan instrumentation of that template's pointer-to-member call
  // (lcm-cpp-impl.hpp:108) passes a wrong object, so the sanitizer build
  // crashed on every LCM message (found by `deploy/edsp sanitize`).
  static void Handle(const lcm::ReceiveBuffer* buffer, const std::string& channel, Subscription* self) {
    self->owner->Dispatch(buffer, channel, &self->handler);
  }
};

std::string EscapeChannelRegex(const std::string& channel) {
  std::string escaped;
  for (char c : channel) {
    if (std::string_view("\\^$.|?*+()[]{}").find(c) != std::string_view::npos) escaped += '\\';
    escaped += c;
  }
  return escaped;
}

LcmTransport::LcmTransport(const std::string& url) : url_(url) {
  lcm_ = std::make_unique<lcm::LCM>(url);
  if (!lcm_->good()) {
    throw TransportError(
        fmt::format("LCM could not start on \"{}\" (bad URL, or no multicast route: see docs/transport.md)", url));
  }
}

LcmTransport::~LcmTransport() = default;

bool LcmTransport::Publish(const std::string& channel, const void* data, std::uint32_t size) noexcept {
  if (lcm_->publish(channel, data, size) == 0) return true;
  ++publish_failures_;
  return false;
}

void LcmTransport::Subscribe(const std::string& channel, RawHandler handler) {
  SubscribePattern(EscapeChannelRegex(channel), std::move(handler));
}

void LcmTransport::SubscribePattern(const std::string& regex, RawHandler handler) {
  auto subscription = std::make_unique<Subscription>(Subscription{this, std::move(handler)});
  if (lcm_->subscribeFunction(regex, &Subscription::Handle, subscription.get()) == nullptr) {
    throw TransportError(fmt::format("LCM refused the subscription \"{}\"", regex));
  }
  subscriptions_.push_back(std::move(subscription));
}

void LcmTransport::Dispatch(const lcm::ReceiveBuffer* buffer, const std::string& channel, RawHandler* handler) {
  ++dispatched_;
  if (pending_error_) return;
  try {
    (*handler)(channel, static_cast<const std::uint8_t*>(buffer->data), buffer->data_size);
  } catch (...) {
    pending_error_ = std::current_exception();  // never through LCM's C frames
  }
}

int LcmTransport::fileno() const { return lcm_->getFileno(); }

bool LcmTransport::Readable() const {
  pollfd fd{fileno(), POLLIN, 0};
  return ::poll(&fd, 1, 0) > 0 && (fd.revents & POLLIN) != 0;
}

int LcmTransport::DrainReady() {
  pollfd fd{fileno(), POLLIN, 0};
  while (::poll(&fd, 1, 0) > 0 && (fd.revents & POLLIN) != 0) {
    if (lcm_->handle() != 0) break;
  }
  return 0;
}

int LcmTransport::Handle(std::chrono::microseconds timeout) {
  dispatched_ = 0;
  const auto us = timeout.count() > 0 ? timeout.count() : 0;
  timespec wait{static_cast<time_t>(us / 1000000), static_cast<long>(us % 1000000) * 1000};
  pollfd fd{fileno(), POLLIN, 0};
  if (::ppoll(&fd, 1, &wait, nullptr) > 0) DrainReady();
  if (pending_error_) {
    std::exception_ptr error = pending_error_;
    pending_error_ = nullptr;
    std::rethrow_exception(error);
  }
  return dispatched_;
}

}  // namespace edsp
