#pragma once
// One writer and any number of readers on a shared-memory channel segment.
// The writer encodes straight into a slot, readers decode straight from it.
// The writer never waits for readers; a reader that falls behind skips ahead
// and counts what it lost. No allocation and no exceptions on these paths.

#include <chrono>
#include <cstdint>
#include <utility>

#include "edsp/transport/futex.h"
#include "edsp/transport/shm_segment.h"

namespace edsp {

std::int64_t NowMicros() noexcept;  // CLOCK_REALTIME, as LCM's utime

class ShmWriter {
 public:
  // Claims the writer role of the channel (see AttachSegmentAsWriter).
  static ShmResult<ShmWriter> Open(const ShmChannelSpec& spec);
  ~ShmWriter();  // orderly exit: releases the writer role and removes the name

  // `encode(std::uint8_t* buffer, std::uint32_t capacity)` writes the message
  // and returns its size, or a negative number if it does not fit. Returns the
  // message number published, or 0 if encode failed (nothing is published).
  template <typename Encode>
  std::uint64_t Publish(Encode&& encode) noexcept;

  std::uint32_t slot_size_bytes() const { return segment_->header()->slot_size_bytes; }
  std::uint64_t published() const;
  const ShmSegment& segment() const { return *segment_; }

  ShmWriter(ShmWriter&&) = delete;  // held by unique_ptr
  explicit ShmWriter(std::unique_ptr<ShmSegment> segment);

 private:
  std::unique_ptr<ShmSegment> segment_;
};

enum class TakeStatus {
  kMessage,      // a message was decoded
  kEmpty,        // nothing new
  kDecodeError,  // the bytes were intact but decode refused them
};

struct ShmReaderStats {
  std::uint64_t received = 0;
  std::uint64_t overruns = 0;  // messages lost because the writer lapped us
  std::uint64_t torn = 0;      // reads discarded because the slot changed under us
  std::uint64_t decode_errors = 0;
};

class ShmReader {
 public:
  static ShmResult<ShmReader> Open(const ShmChannelSpec& spec);
  explicit ShmReader(std::unique_ptr<ShmSegment> segment);

  // Decodes the next message in order: `decode(const std::uint8_t* data,
  // std::uint32_t size)` returns true if it accepted the bytes. Its output is
  // only valid when kMessage is returned (a torn slot is retried, not
  // delivered). `message_number` receives the message's number n.
  template <typename Decode>
  TakeStatus TryTake(Decode&& decode, std::uint64_t* message_number = nullptr) noexcept;

  // Skips to the newest message (control loops want the latest, not a backlog).
  // Skipped messages are not overruns.
  void SkipToLatest() noexcept;

  // Back to the newest message published before this reader attached, if
  // any (a new reader otherwise starts after it): a restarted process
  // reading the last state its dead predecessor published.
  void RewindToLatest() noexcept;

  // Back to the segment's first message: a reader that subscribed before
  // this writer's segment existed (a recorder) takes everything it
  // published; what the ring no longer holds counts as overruns.
  void RewindToFirst() noexcept { next_ = 1; }

  // Waits until a message is available or `timeout` passes: spins for
  // `spin` first, then sleeps on the futex. Returns true if one is available.
  bool Wait(std::chrono::nanoseconds timeout, std::chrono::nanoseconds spin = std::chrono::microseconds(20)) noexcept;

  // Waits until any of `readers` has a message or `timeout` passes, spinning
  // for `spin` first, then sleeping on all their doorbells at once (one
  // futex_waitv). Returns true if one is available. With `extra`, it also
  // returns once *extra != extra_expected (another source's doorbell: an
  // FdDoorbell of the LCM socket).
  static bool WaitAny(ShmReader* const* readers, int count, std::chrono::nanoseconds timeout,
                      std::chrono::nanoseconds spin = std::chrono::microseconds(20),
                      std::atomic<std::uint32_t>* extra = nullptr, std::uint32_t extra_expected = 0) noexcept;

  bool Available() const noexcept;
  bool WriterAlive() const;
  // The writer closed the ring (a clean exit): one atomic load, where
  // WriterAlive also looks a killed writer up in /proc (tens of µs).
  bool WriterLeft() const noexcept;
  std::uint32_t writer_generation() const;
  const ShmReaderStats& stats() const { return stats_; }
  std::uint64_t next_message() const { return next_; }
  const ShmSegment& segment() const { return *segment_; }

 private:
  std::unique_ptr<ShmSegment> segment_;
  std::uint64_t next_ = 1;  // number of the next message to read
  ShmReaderStats stats_;
};

// ---- inline protocol ------------------------------------------------------

template <typename Encode>
std::uint64_t ShmWriter::Publish(Encode&& encode) noexcept {
  ShmSegmentHeader* h = segment_->header();
  const std::uint64_t n = h->published.load(std::memory_order_relaxed) + 1;
  ShmSlotHeader* slot = segment_->slot(n);
  slot->sequence.store(2 * n - 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);  // odd before any payload byte
  const auto size = encode(segment_->payload(slot), h->slot_size_bytes);
  if (size < 0 || static_cast<std::uint64_t>(size) > h->slot_size_bytes) {
    // The slot stays odd ("message n being written"): a reader waiting for n
    // keeps waiting, a lapped reader still sees it was overtaken. The next
    // Publish rewrites it as message n.
    return 0;
  }
  slot->size_bytes = static_cast<std::uint32_t>(size);
  slot->publish_utime = NowMicros();
  slot->sequence.store(2 * n, std::memory_order_release);
  // seq_cst against the readers' sleepers/published handshake (see Wait):
  // either we see a sleeper and ring, or it sees `published` and never sleeps.
  // Nobody asleep: no doorbell write, so spinning readers' lines stay quiet.
  h->published.store(n, std::memory_order_seq_cst);
  if (h->sleepers.load(std::memory_order_seq_cst) > 0) {
    h->doorbell.fetch_add(1, std::memory_order_seq_cst);
    FutexWakeAll(&h->doorbell);
  }
  return n;
}

template <typename Decode>
TakeStatus ShmReader::TryTake(Decode&& decode, std::uint64_t* message_number) noexcept {
  ShmSegmentHeader* h = segment_->header();
  const std::uint64_t slots = h->slot_count;
  for (;;) {
    // The slot's own sequence says whether message next_ is there; the shared
    // `published` counter is only read when we may have been lapped, so a
    // spinning reader polls one cache line the writer touches once per message.
    ShmSlotHeader* slot = segment_->slot(next_);
    const std::uint64_t before = slot->sequence.load(std::memory_order_acquire);
    if (before < 2 * next_) return TakeStatus::kEmpty;  // not written yet (or in progress)
    if (before != 2 * next_) {
      const std::uint64_t published = h->published.load(std::memory_order_acquire);
      // 2^62 messages would take 146 000 years at 1 MHz: a count that high is
      // a corrupt header, and 2·next_ would overflow (fuzz_shm_segment).
      if (published >= kShmMaxMessages) return TakeStatus::kEmpty;
      if (published >= next_ && published - next_ >= slots) {  // lapped: jump to the oldest
        const std::uint64_t oldest = published - slots + 1;
        stats_.overruns += oldest - next_;
        next_ = oldest;
      } else {
        // Rewritten for a later lap while we looked: message next_ is lost.
        // That needs the writer to have published next_ at least; a slot
        // ahead of the writer's own count is a foreign or corrupt ring, and
        // skipping on would spin through it (found by fuzz_shm_segment).
        if (next_ > published) return TakeStatus::kEmpty;
        ++stats_.overruns;
        ++next_;
      }
      continue;
    }
    std::uint32_t size = slot->size_bytes;
    if (size > h->slot_size_bytes) size = h->slot_size_bytes;  // torn size: bounded
    const bool accepted = decode(static_cast<const std::uint8_t*>(segment_->payload(slot)), size);
    std::atomic_thread_fence(std::memory_order_acquire);
    const std::uint64_t after = slot->sequence.load(std::memory_order_relaxed);
    const std::uint64_t number = next_++;
    if (after != before) {
      ++stats_.torn;
      ++stats_.overruns;
      continue;
    }
    if (message_number != nullptr) *message_number = number;
    if (!accepted) {
      ++stats_.decode_errors;
      return TakeStatus::kDecodeError;
    }
    ++stats_.received;
    return TakeStatus::kMessage;
  }
}

}  // namespace edsp
