#pragma once
// A client's side of request_service.h, for edsp-ctl, the Python Platform
// and the planner's motion client alike: a request goes out with a fresh
// request_id, stamped once, and is sent again every 0.5 s until the reply
// with that id comes, or the timeout. Copies keep the first stamp: the
// node's window then bounds when any copy can still be taken (its reply
// cache outlives it), and a late copy stays as old as the request was.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

class RequestClient {
 public:
  static constexpr std::chrono::milliseconds kResend{500};

  explicit RequestClient(Bus& bus) : bus_(bus) {}

  // Random, never 0: clients on several hosts need no coordination.
  static std::int64_t NewRequestId();

  // `request` (its session, id and fields the caller's) on `channel` until
  // its reply on `reply_channel`, or none within `timeout_s`. Throws
  // std::runtime_error naming the channel if it cannot be sent.
  template <typename Reply, typename Request>
  std::optional<Reply> Send(const std::string& channel, const std::string& reply_channel, Request request,
                            double timeout_s) {
    using Clock = std::chrono::steady_clock;
    const auto until =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
    Start<Reply>(channel, reply_channel, std::move(request));
    while (!Answer<Reply>(reply_channel) && Clock::now() < until) {
      ResendIfDue();
      bus_.Handle(std::chrono::milliseconds(20));
    }
    return Answer<Reply>(reply_channel);
  }

  // The same without waiting, for a node whose cycle cannot block: Start
  // sends the request; each cycle, ResendIfDue sends it again every kResend
  // until Answer has its reply (the bus handled by the node's own loop).
  // One request in flight at a time: a new Start replaces the last.
  template <typename Reply, typename Request>
  void Start(const std::string& channel, const std::string& reply_channel, Request request) {
    Inbox<Reply>& inbox = InboxFor<Reply>(reply_channel);
    inbox.awaited = request.request_id;
    inbox.reply.reset();
    request.utime = UtimeNow();
    answered_ = [&inbox] { return inbox.reply.has_value(); };
    resend_ = [this, channel, request]() mutable {
      ++request.seq;
      if (!bus_.Publish(channel, request)) throw std::runtime_error(channel + " could not be sent");
    };
    next_send_ = std::chrono::steady_clock::now();
    ResendIfDue();
  }
  void ResendIfDue() {
    if (!resend_ || answered_() || std::chrono::steady_clock::now() < next_send_) return;
    resend_();
    next_send_ = std::chrono::steady_clock::now() + kResend;
  }
  // The reply to the request last started on `reply_channel`, once it came.
  template <typename Reply>
  const std::optional<Reply>& Answer(const std::string& reply_channel) {
    return InboxFor<Reply>(reply_channel).reply;
  }

 private:
  template <typename Reply>
  struct Inbox {
    std::int64_t awaited = 0;
    std::optional<Reply> reply;
  };

  // Subscribed once per reply channel (Bus has no unsubscribe); the handler
  // shares ownership of what it fills.
  template <typename Reply>
  Inbox<Reply>& InboxFor(const std::string& reply_channel) {
    auto& slot = inboxes_[reply_channel];
    if (!slot) {
      auto inbox = std::make_shared<Inbox<Reply>>();
      bus_.Subscribe<Reply>(reply_channel, [inbox](const Reply& r) {
        if (r.request_id == inbox->awaited) inbox->reply = r;
      });
      slot = inbox;
    }
    return *std::static_pointer_cast<Inbox<Reply>>(slot);
  }

  Bus& bus_;
  std::map<std::string, std::shared_ptr<void>> inboxes_;
  std::function<bool()> answered_;  // the request in flight: its reply came
  std::function<void()> resend_;    // sends it once more (its seq advanced)
  std::chrono::steady_clock::time_point next_send_;
};

}  // namespace edsp
