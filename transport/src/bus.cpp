#include "edsp/transport/bus.h"

#include <poll.h>

#include <algorithm>
#include <thread>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/transport/channel_pattern.h"

namespace edsp {

namespace {
// How often a reader looks again for a ring it has not found. A node
// starts from the newest message; every look that finds nothing costs an
// exception inside Boost.Interprocess, which a SCHED_FIFO node should not
// pay 100 times a second. A recorder reads a ring it found late from its
// first message, which stays there for slots / rate (64 ms at 1 kHz): it
// looks well within that, or it loses the first messages of a ring that
// appears while it runs.
constexpr auto kAttachRetry = std::chrono::milliseconds(100);
constexpr auto kRecorderAttachRetry = std::chrono::milliseconds(10);
// A recorder's rings are read at this pace, not slept on: a reader asleep
// on a ring makes every message of it a wake-up by its writer, on a 1 kHz
// hot path a cross-CPU one at the writer's expense, for a reader that
// needs no latency. A 64-slot ring at 1 kHz holds 64 ms.
constexpr auto kRecorderPoll = std::chrono::milliseconds(5);
// A recorder skips the LCM copies of a channel whose ring is not written
// yet (its writer on this host is starting: the ring, read from its first
// message, will hold them all). Copies that keep coming this long with no
// ring mean the writer is not on this host (or publishes on LCM only): they
// are recorded from then on, and it is said.
constexpr auto kRingGrace = std::chrono::seconds(1);
// With both LCM and shared-memory inputs, an FdDoorbell turns LCM's socket
// into one more futex word beside the segments' doorbells; this slice only
// bounds a wait in case a wake-up were ever missed.
constexpr auto kMixedWaitSlice = std::chrono::seconds(1);
// An LCM provider without a file descriptor to poll: LCM is looked at
// between slices this long instead.
constexpr auto kMixedPollSlice = std::chrono::microseconds(500);
}  // namespace

Bus::Bus(TransportConfig config) : config_(std::move(config)), lcm_(config_.lcm_url) {}

Bus::~Bus() = default;

void Bus::CheckChannelType(const std::string& channel, const char* type_name) {
  const channel::Channel* row = channel::Find(channel);
  if (row != nullptr && row->type != type_name) {
    throw TransportError(fmt::format("{} carries {} (channels.h), not {}", channel, row->type, type_name));
  }
}

const ChannelCounters& Bus::Counters(const std::string& channel) { return counters_[channel]; }

Bus::PublisherState& Bus::StateFor(const std::string& channel, std::int64_t fingerprint) {
  auto it = publishers_.find(channel);
  if (it != publishers_.end()) {
    if (it->second->fingerprint != fingerprint) {
      throw TransportError(fmt::format("{}: published with two different message types", channel));
    }
    return *it->second;
  }
  auto state = std::make_unique<PublisherState>();
  state->channel = channel;
  state->route = config_.Route(channel);
  state->fingerprint = fingerprint;
  state->counters = &counters_[channel];
  if (state->route.path != ChannelPath::kLcm) {
    ShmChannelSpec spec{config_.SegmentName(channel), fingerprint, state->route.slots, state->route.slot_size_bytes,
                        config_.shm_permissions};
    ShmResult<ShmWriter> writer = ShmWriter::Open(spec);
    if (!writer.ok()) {
      throw TransportError(fmt::format("channel {}: {} ({})", channel, writer.message, ShmErrorName(writer.error)));
    }
    state->writer = std::move(writer.value);
  }
  return *publishers_.emplace(channel, std::move(state)).first->second;
}

void Bus::Mirror(PublisherState& s, std::uint64_t n) noexcept {
  // The slot we just filled holds the encoded message: send those bytes, no
  // second encode. Nothing else writes this slot until the ring wraps.
  const ShmSegment& segment = s.writer->segment();
  ShmSlotHeader* slot = segment.slot(n);
  if (lcm_.Publish(s.channel, segment.payload(slot), slot->size_bytes)) {
    ++s.counters->mirrored;
  } else {
    ++s.counters->publish_failures;
  }
}

Bus::ShmSubscription& Bus::AddShmSubscription(const std::string& channel, std::int64_t fingerprint,
                                              std::function<TakeStatus(ShmReader&)> take, bool recorder) {
  auto subscription = std::make_unique<ShmSubscription>();
  const ChannelRoute& route = config_.Route(channel);
  subscription->spec = ShmChannelSpec{config_.SegmentName(channel), fingerprint, route.slots, route.slot_size_bytes,
                                      config_.shm_permissions,      recorder};
  subscription->take = std::move(take);
  subscription->counters = &counters_[channel];
  subscription->recorder = recorder;
  Attach(*subscription, true);  // the writer may not be up yet: retried in Handle
  shm_subscriptions_.push_back(std::move(subscription));
  return *shm_subscriptions_.back();
}

bool Bus::Attach(ShmSubscription& s, bool at_subscribe) {
  const auto now = std::chrono::steady_clock::now();
  if (now < s.next_attach) return false;
  s.next_attach = now + (s.recorder ? kRecorderAttachRetry : kAttachRetry);
  ShmResult<ShmReader> reader = ShmReader::Open(s.spec);
  if (!reader.ok()) {
    if (reader.error != ShmError::kNotFound && reader.error != ShmError::kNotReady) {
      s.counters->last_error = reader.message;  // wrong type, corrupt: say so, keep trying
      s.refused = true;
    }
    return false;
  }
  s.reader = std::move(reader.value);
  s.refused = false;
  if (s.recorder && !at_subscribe) s.reader->RewindToFirst();  // all of it came after we subscribed
  s.counters->last_error.clear();
  return true;
}

int Bus::DrainShm() {
  int delivered = 0;
  for (auto& s : shm_subscriptions_) {
    if (s->reader == nullptr && !Attach(*s)) continue;
    const std::uint64_t overruns_before = s->reader->stats().overruns;
    for (;;) {
      TakeStatus status;
      try {
        status = s->take(*s->reader);
      } catch (...) {
        Fail(std::current_exception());
        break;
      }
      if (status == TakeStatus::kEmpty) break;
      if (status == TakeStatus::kMessage) ++delivered;
    }
    s->counters->overruns += s->reader->stats().overruns - overruns_before;
    // A writer that exited in order removed its segment; a new one made
    // another. Follow it (a writer restarted after kill -9 re-attaches to the
    // same segment and needs nothing). Whether the writer lives is read from
    // /proc (tens of µs): at the attach retry's pace, which paces the reopen
    // anyway, not on every drain, which at 1 kHz on a few rings cost a node
    // more than its own work.
    const auto now = std::chrono::steady_clock::now();
    if (now >= s->next_attach) {
      s->next_attach = now + (s->recorder ? kRecorderAttachRetry : kAttachRetry);
      if (s->reader->WriterAlive()) continue;
      ShmResult<ShmReader> fresh = ShmReader::Open(s->spec);
      if (fresh.ok() && fresh.value->WriterAlive()) {
        s->reader = std::move(fresh.value);
        s->refused = false;
        if (s->recorder) s->reader->RewindToFirst();  // the new writer's first messages too
      } else if (!fresh.ok() && fresh.error != ShmError::kNotFound && fresh.error != ShmError::kNotReady) {
        s->counters->last_error = fresh.message;  // the new writer's ring cannot be read
        s->refused = true;
      }
    }
  }
  return delivered;
}

bool Bus::SkipsLcmCopy(ShmSubscription& ring) {
  if (ring.refused) return false;           // (a restarted writer's ring refused: the old reader stays, dead)
  if (ring.reader != nullptr) return true;  // its mirror: the ring has all of it
  // Not written yet: read from its first message once found, the ring will
  // have this copy too.
  const auto now = std::chrono::steady_clock::now();
  if (!ring.first_copy_without_ring) ring.first_copy_without_ring = now;
  if (now - *ring.first_copy_without_ring < kRingGrace) {
    ++ring.counters->copies_awaiting_ring;
    return true;
  }
  ring.refused = true;
  ring.counters->last_error =
      fmt::format("no ring written on this host after {} s of LCM copies ({} skipped)",
                  std::chrono::duration<double>(kRingGrace).count(), ring.counters->copies_awaiting_ring);
  return false;
}

std::vector<std::string> Bus::SubscribeRaw(const std::string& pattern, RawHandler handler) {
  const ChannelPattern names(pattern);
  // Channel → its ring, for the LCM side to skip what the ring delivers.
  auto rings = std::make_shared<std::unordered_map<std::string, ShmSubscription*>>();
  lcm_.SubscribePattern(
      names.ForLcm(), [this, rings, handler](const std::string& channel, const std::uint8_t* data, std::uint32_t size) {
        const auto ring = rings->find(channel);
        if (ring != rings->end() && SkipsLcmCopy(*ring->second)) return;
        ++counters_[channel].received;
        handler(channel, data, size);
      });
  std::vector<std::string> channels;
  for (const auto& entry : config_.channels) {
    const std::string& channel = entry.first;  // a named variable: lambdas capture it (C++17)
    if (entry.second.path == ChannelPath::kLcm || !names.Matches(channel)) continue;
    channels.push_back(channel);  // config_.channels is a std::map: sorted
    auto bytes = std::make_shared<std::vector<std::uint8_t>>();
    ChannelCounters* counters = &counters_[channel];
    auto take = [channel, bytes, counters, handler](ShmReader& reader) {
      const TakeStatus status = reader.TryTake([&](const std::uint8_t* data, std::uint32_t size) {
        bytes->assign(data, data + size);  // a slot rewritten meanwhile is skipped, counted as an overrun
        return true;
      });
      if (status == TakeStatus::kMessage) {
        ++counters->received;
        handler(channel, bytes->data(), static_cast<std::uint32_t>(bytes->size()));
      }
      return status;
    };
    (*rings)[channel] = &AddShmSubscription(channel, 0, std::move(take), /*recorder=*/true);
  }
  return channels;
}

void Bus::Fail(std::exception_ptr error) {
  if (!pending_error_) pending_error_ = error;
}

bool Bus::WaitShm(std::chrono::steady_clock::duration timeout, FdDoorbell* lcm_bell) {
  ShmReader* readers[64];
  int count = 0;
  for (auto& sub : shm_subscriptions_) {
    if (sub->reader != nullptr && !sub->recorder && count < 64) readers[count++] = sub->reader.get();
  }
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout);
  // No spinning before the sleep: a node spins at its real-time priority,
  // above the stage that feeds it on the same CPU (the hot path shares
  // one), so a spin only holds off the message it waits for, and on a slow
  // machine it is CPU time the real-time budget lacks. The futex wakes in
  // microseconds.
  constexpr std::chrono::nanoseconds kNoSpin{0};
  if (lcm_bell != nullptr) {
    // Read the bell before looking at the socket: a message that arrives
    // after the look changes the word, and the wait returns at once.
    const std::uint32_t rung = lcm_bell->word()->load(std::memory_order_seq_cst);
    if (lcm_.Readable()) return true;
    return ShmReader::WaitAny(readers, count, ns, kNoSpin, lcm_bell->word(), rung);
  }
  if (count == 0) {
    std::this_thread::sleep_for(timeout);
    return false;
  }
  return ShmReader::WaitAny(readers, count, ns, kNoSpin);
}

int Bus::Handle(std::chrono::microseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  int delivered = 0;
  for (;;) {
    delivered += DrainShm();
    const auto now = Clock::now();
    const auto remaining = delivered > 0 || now >= deadline ? Clock::duration::zero() : deadline - now;
    if (shm_subscriptions_.empty()) {
      delivered += lcm_.Handle(std::chrono::duration_cast<std::chrono::microseconds>(remaining));
    } else {
      // Sleep on every shm doorbell, and LCM's socket's, at once; a segment
      // not attached yet is retried per slice.
      const bool mixed = lcm_.subscription_count() > 0;
      if (mixed && lcm_bell_ == nullptr && lcm_.fileno() >= 0) lcm_bell_ = std::make_unique<FdDoorbell>(lcm_.fileno());
      const bool all_attached = std::all_of(shm_subscriptions_.begin(), shm_subscriptions_.end(),
                                            [](const auto& sub) { return sub->reader != nullptr; });
      auto slice = remaining;
      if (mixed)
        slice = std::min<Clock::duration>(
            slice, lcm_bell_ ? Clock::duration(kMixedWaitSlice) : Clock::duration(kMixedPollSlice));
      if (!all_attached) slice = std::min<Clock::duration>(slice, kAttachRetry);
      if (std::any_of(shm_subscriptions_.begin(), shm_subscriptions_.end(),
                      [](const auto& sub) { return sub->recorder; })) {
        slice = std::min<Clock::duration>(slice, kRecorderPoll);
      }
      if (slice > Clock::duration::zero()) WaitShm(slice, lcm_bell_.get());
      delivered += DrainShm();
      if (mixed) {
        delivered += lcm_.Handle(std::chrono::microseconds(0));
        if (lcm_bell_) lcm_bell_->Drained();
      }
    }
    if (pending_error_) {
      std::exception_ptr error = pending_error_;
      pending_error_ = nullptr;
      std::rethrow_exception(error);
    }
    if (delivered > 0 || Clock::now() >= deadline) return delivered;
  }
}

}  // namespace edsp
