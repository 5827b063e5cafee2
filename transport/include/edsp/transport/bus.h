#pragma once
// edsp::Bus: typed publish/subscribe of lcm-gen types on named channels, one
// API whatever the path. The path of each channel (LCM, shared memory, or
// both with an optionally decimated LCM mirror) comes from TransportConfig,
// i.e. the deploy group file, never from the code that publishes.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "edsp/transport/decode.h"
#include "edsp/transport/error.h"
#include "edsp/transport/fd_doorbell.h"
#include "edsp/transport/lcm_transport.h"
#include "edsp/transport/seq_gap.h"
#include "edsp/transport/shm_channel.h"
#include "edsp/transport/transport_config.h"

namespace edsp {

// What happened on one channel in this process; the source of EDSP_STATUS.
struct ChannelCounters {
  std::uint64_t published = 0;
  std::uint64_t publish_failures = 0;  // LCM refused, or too big for a slot
  std::uint64_t mirrored = 0;          // shm messages also sent on LCM
  std::uint64_t received = 0;
  std::uint64_t decode_errors = 0;         // truncated or foreign packets
  std::uint64_t overruns = 0;              // shm messages lost to a lapping writer
  std::uint64_t seq_gaps = 0;              // messages missing by their `seq` field
  std::uint64_t copies_awaiting_ring = 0;  // a recorder's LCM copies skipped: the ring not written yet
  std::string last_error;                  // newest problem, for EDSP_FAULT
};

class Bus {
  struct PublisherState;

 public:
  // Opens LCM at config.lcm_url; throws TransportError naming it on failure.
  explicit Bus(TransportConfig config = {});
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  // A publishing handle with no per-message lookup (control loops hold one).
  template <typename Msg>
  class Publisher {
   public:
    bool Publish(const Msg& msg) noexcept { return bus_->PublishEncoded(*state_, msg); }
    const ChannelCounters& counters() const;

   private:
    friend class Bus;
    Publisher(Bus* bus, typename Bus::PublisherState* state) : bus_(bus), state_(state) {}
    Bus* bus_;
    typename Bus::PublisherState* state_;
  };

  // Set-up: opens the channel's shared-memory segment if it is routed there.
  // Throws TransportError (segment taken by a live writer, wrong type, ...).
  template <typename Msg>
  Publisher<Msg> Advertise(const std::string& channel);

  // Convenience: Advertise on first use, then publish. Returns false if the
  // message was not sent (counted in the channel's counters).
  template <typename Msg>
  bool Publish(const std::string& channel, const Msg& msg) {
    return Advertise<Msg>(channel).Publish(msg);
  }

  // Handlers run inside Handle(). A message that does not decode (foreign
  // type, truncated) is counted and dropped, never handed over.
  template <typename Msg>
  void Subscribe(const std::string& channel, std::function<void(const Msg&)> handler);

  // For a recorder (the logger): the bytes of every channel whose whole name
  // matches `pattern` (a POSIX extended regex, anchored at both ends as a
  // whole: `A|B` is A or B), undecoded. A channel this process reads on
  // shared memory (its route, as RoutesForMember gave it) is taken there,
  // every message, and its LCM copy (at most a decimated mirror) is skipped
  // while the ring is attached or not written yet: a ring found only after
  // subscribing, or made anew by a restarted writer, is read from its first
  // message, so a mirror copy taken before would be recorded twice. A ring
  // that is there but refused, or that has not come 1 s after the first LCM
  // copy did (its writer is on another host, or LCM only), leaves the
  // channel its LCM copy, and `last_error` says why. The others come from LCM. Counts `received` (and
  // `overruns` on shared memory) per channel; seq gaps need the message's
  // header and are the caller's. Returns the shared-memory channels. The
  // Bus has no unsubscribe: it must not be handled once `handler` is gone.
  // Throws TransportError naming a pattern that is no regex.
  using RawHandler = LcmTransport::RawHandler;
  std::vector<std::string> SubscribeRaw(const std::string& pattern, RawHandler handler);

  // Waits up to `timeout` for the first message, then dispatches everything
  // pending. Returns the number dispatched. Rethrows a handler's exception.
  // It sleeps on LCM's socket, or on all shared-memory channels at once; with
  // both kinds of input, on all of them at once too (an FdDoorbell thread
  // watches LCM's socket), so either wakes it at once. A recorder's rings
  // (SubscribeRaw) are the exception: read every 5 ms, never slept on.
  int Handle(std::chrono::microseconds timeout);

  const ChannelCounters& Counters(const std::string& channel);
  const TransportConfig& config() const { return config_; }
  LcmTransport& lcm() { return lcm_; }

 private:
  struct PublisherState {
    std::string channel;
    ChannelRoute route;
    std::int64_t fingerprint = 0;
    std::unique_ptr<ShmWriter> writer;
    std::vector<std::uint8_t> buffer;  // LCM encode buffer, grown once
    ChannelCounters* counters = nullptr;
  };
  struct ShmSubscription {
    ShmChannelSpec spec;
    std::unique_ptr<ShmReader> reader;
    std::function<TakeStatus(ShmReader&)> take;  // decode + dispatch one message
    ChannelCounters* counters = nullptr;
    std::chrono::steady_clock::time_point next_attach{};
    // A raw recorder's (SubscribeRaw): any type, and a segment it finds
    // only after subscribing is read from its first message.
    bool recorder = false;
    // The segment is there but cannot be read (another layout or type,
    // permissions, not edsp's), or never came while LCM copies did: its
    // LCM copy is all there is.
    bool refused = false;
    // A recorder's: when the first LCM copy came with no ring yet.
    std::optional<std::chrono::steady_clock::time_point> first_copy_without_ring;
  };

  PublisherState& StateFor(const std::string& channel, std::int64_t fingerprint);
  // A channel of edsp's table (channels.h) carries its one type: another is
  // a programming error, refused at set-up with a TransportError.
  static void CheckChannelType(const std::string& channel, const char* type_name);
  template <typename Msg>
  bool PublishEncoded(PublisherState& state, const Msg& msg) noexcept;
  void Mirror(PublisherState& state, std::uint64_t message_number) noexcept;
  ShmSubscription& AddShmSubscription(const std::string& channel, std::int64_t fingerprint,
                                      std::function<TakeStatus(ShmReader&)> take, bool recorder = false);
  bool Attach(ShmSubscription& subscription, bool at_subscribe = false);
  // A recorder's LCM copy of a shared-memory channel: skipped while its ring
  // has (or, not written yet, will have) it; recorded when the ring is
  // refused, or never came within a grace while copies did.
  bool SkipsLcmCopy(ShmSubscription& ring);
  int DrainShm();
  bool WaitShm(std::chrono::steady_clock::duration timeout, FdDoorbell* lcm_bell);
  void Fail(std::exception_ptr error);
  template <typename Msg>
  void Delivered(ChannelCounters& counters, const Msg& msg, SeqTracker* seqs);

  TransportConfig config_;
  LcmTransport lcm_;
  std::unordered_map<std::string, std::unique_ptr<PublisherState>> publishers_;
  std::unordered_map<std::string, ChannelCounters> counters_;
  std::vector<std::unique_ptr<ShmSubscription>> shm_subscriptions_;
  std::exception_ptr pending_error_;
  std::unique_ptr<FdDoorbell> lcm_bell_;  // mixed inputs only, made on first need
};

// ---- templates -------------------------------------------------------------

namespace detail {
template <typename T, typename = void>
struct HasSeq : std::false_type {};
template <typename T>
struct HasSeq<T, std::void_t<decltype(std::declval<T>().seq)>> : std::true_type {};
template <typename T, typename = void>
struct HasSessionId : std::false_type {};
template <typename T>
struct HasSessionId<T, std::void_t<decltype(std::declval<T>().session_id)>> : std::true_type {};
}  // namespace detail

template <typename Msg>
const ChannelCounters& Bus::Publisher<Msg>::counters() const {
  return *state_->counters;
}

template <typename Msg>
Bus::Publisher<Msg> Bus::Advertise(const std::string& channel) {
  CheckChannelType(channel, Msg::getTypeName());
  return Publisher<Msg>(this, &StateFor(channel, Msg::getHash()));
}

template <typename Msg>
bool Bus::PublishEncoded(PublisherState& s, const Msg& msg) noexcept {
  const int size = msg.getEncodedSize();
  if (s.writer != nullptr) {
    const std::uint64_t n = s.writer->Publish([&](std::uint8_t* buffer, std::uint32_t capacity) -> std::int64_t {
      if (size < 0 || static_cast<std::uint32_t>(size) > capacity) return -1;
      return msg.encode(buffer, 0, static_cast<int>(capacity));
    });
    if (n == 0) {
      ++s.counters->publish_failures;
      return false;
    }
    ++s.counters->published;
    if (s.route.path == ChannelPath::kBoth && n % s.route.mirror_every == 0) Mirror(s, n);
    return true;
  }
  if (size < 0) return false;
  if (s.buffer.size() < static_cast<std::size_t>(size)) s.buffer.resize(static_cast<std::size_t>(size));
  // What encode wrote, not getEncodedSize(): lcm-gen's encoder stops a
  // string at an embedded NUL where its size counts the whole std::string
  // (found by fuzz_lcm_decode), and the rest of the buffer is not the message.
  const int written = msg.encode(s.buffer.data(), 0, size);
  if (written < 0 || !lcm_.Publish(s.channel, s.buffer.data(), static_cast<std::uint32_t>(written))) {
    ++s.counters->publish_failures;
    return false;
  }
  ++s.counters->published;
  return true;
}

template <typename Msg>
void Bus::Delivered(ChannelCounters& counters, const Msg& msg, SeqTracker* seqs) {
  ++counters.received;
  if constexpr (detail::HasSeq<Msg>::value) {
    std::int64_t session = 0;
    if constexpr (detail::HasSessionId<Msg>::value) session = msg.session_id;
    counters.seq_gaps += static_cast<std::uint64_t>(seqs->Count(session, msg.seq));
  }
}

template <typename Msg>
void Bus::Subscribe(const std::string& channel, std::function<void(const Msg&)> handler) {
  CheckChannelType(channel, Msg::getTypeName());
  const ChannelRoute& route = config_.Route(channel);
  ChannelCounters* counters = &counters_[channel];
  auto last_seq = std::make_shared<SeqTracker>();
  if (route.path == ChannelPath::kLcm) {
    lcm_.Subscribe(channel, [this, channel, counters, last_seq, handler = std::move(handler)](
                                const std::string&, const std::uint8_t* data, std::uint32_t size) {
      Msg msg;
      if (!DecodeUntrusted(&msg, data, size)) {
        ++counters->decode_errors;
        counters->last_error = channel + ": dropped a packet that is not a valid " + std::string(typeid(Msg).name()) +
                               " (" + std::to_string(size) + " bytes: truncated or foreign type)";
        return;
      }
      Delivered(*counters, msg, last_seq.get());
      handler(msg);
    });
    return;
  }
  auto msg = std::make_shared<Msg>();
  AddShmSubscription(channel, Msg::getHash(),
                     [this, counters, msg, last_seq, handler = std::move(handler)](ShmReader& reader) {
                       const TakeStatus status = reader.TryTake([&](const std::uint8_t* data, std::uint32_t size) {
                         return DecodeUntrusted(msg.get(), data, size);  // a torn length field is a bad message
                       });
                       if (status == TakeStatus::kMessage) {
                         Delivered(*counters, *msg, last_seq.get());
                         handler(*msg);
                       } else if (status == TakeStatus::kDecodeError) {
                         ++counters->decode_errors;
                       }
                       return status;
                     });
}

}  // namespace edsp
