#include "edsp/transport/shm_channel.h"

#include <time.h>

#include <algorithm>
#include <mutex>
#include <set>
#include <thread>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define EDSP_CPU_RELAX() _mm_pause()
#else
#define EDSP_CPU_RELAX() std::this_thread::yield()
#endif

namespace edsp {

std::int64_t NowMicros() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1000000 + ts.tv_nsec / 1000;
}

ShmWriter::ShmWriter(std::unique_ptr<ShmSegment> segment) : segment_(std::move(segment)) {}

namespace {

// Segments this process writes: the header's pid cannot tell two writers of
// one process apart, so the second is refused here.
std::mutex& WritersMutex() {
  static std::mutex mutex;
  return mutex;
}
std::set<std::string>& LocalWriters() {
  static std::set<std::string> names;
  return names;
}

}  // namespace

ShmResult<ShmWriter> ShmWriter::Open(const ShmChannelSpec& spec) {
  ShmResult<ShmWriter> result;
  std::lock_guard<std::mutex> lock(WritersMutex());
  if (LocalWriters().count(spec.segment_name) != 0) {
    result.error = ShmError::kWriterAlive;
    result.message = spec.segment_name + ": this process already writes it";
    return result;
  }
  ShmResult<ShmSegment> segment = AttachSegmentAsWriter(spec);
  result.error = segment.error;
  result.message = std::move(segment.message);
  if (segment.ok()) {
    result.value = std::make_unique<ShmWriter>(std::move(segment.value));
    LocalWriters().insert(spec.segment_name);
  }
  return result;
}

ShmWriter::~ShmWriter() {
  {
    std::lock_guard<std::mutex> lock(WritersMutex());
    LocalWriters().erase(segment_->name());
  }
  ShmSegmentHeader* h = segment_->header();
  if (h->writer_pid.load(std::memory_order_acquire) != CurrentPid()) return;  // taken over
  h->writer_pid.store(0, std::memory_order_release);
  h->doorbell.fetch_add(1, std::memory_order_seq_cst);
  FutexWakeAll(&h->doorbell);  // sleeping readers notice the writer left
  RemoveSegment(segment_->name());
}

std::uint64_t ShmWriter::published() const { return segment_->header()->published.load(std::memory_order_acquire); }

ShmReader::ShmReader(std::unique_ptr<ShmSegment> segment) : segment_(std::move(segment)) {
  // A new reader starts with the next message published after it attached.
  next_ = segment_->header()->published.load(std::memory_order_acquire) + 1;
}

ShmResult<ShmReader> ShmReader::Open(const ShmChannelSpec& spec) {
  ShmResult<ShmSegment> segment = AttachSegmentAsReader(spec);
  ShmResult<ShmReader> result;
  result.error = segment.error;
  result.message = std::move(segment.message);
  if (segment.ok()) result.value = std::make_unique<ShmReader>(std::move(segment.value));
  return result;
}

void ShmReader::SkipToLatest() noexcept {
  const std::uint64_t published = segment_->header()->published.load(std::memory_order_acquire);
  if (published >= next_) next_ = published;
}

void ShmReader::RewindToLatest() noexcept {
  const std::uint64_t published = segment_->header()->published.load(std::memory_order_acquire);
  if (published >= 1 && published < kShmMaxMessages) next_ = published;
}

bool ShmReader::Available() const noexcept {
  return segment_->header()->published.load(std::memory_order_acquire) >= next_;
}

bool ShmReader::Wait(std::chrono::nanoseconds timeout, std::chrono::nanoseconds spin) noexcept {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto deadline = start + timeout;
  const auto spin_until = start + std::min(spin, timeout);
  while (Clock::now() < spin_until) {
    for (int i = 0; i < 64; ++i) {
      if (Available()) return true;
      EDSP_CPU_RELAX();
    }
  }
  ShmSegmentHeader* h = segment_->header();
  for (;;) {
    const std::uint32_t bell = h->doorbell.load(std::memory_order_seq_cst);
    if (Available()) return true;
    const auto now = Clock::now();
    if (now >= deadline) return false;
    h->sleepers.fetch_add(1, std::memory_order_seq_cst);
    // Re-check after announcing ourselves: the writer either sees us as a
    // sleeper and wakes us, or we see its message here (seq_cst both sides).
    if (Available()) {
      h->sleepers.fetch_sub(1, std::memory_order_seq_cst);
      return true;
    }
    FutexWait(&h->doorbell, bell, deadline - now);
    h->sleepers.fetch_sub(1, std::memory_order_seq_cst);
    if (h->writer_pid.load(std::memory_order_acquire) == 0 && !Available()) return false;
  }
}

bool ShmReader::WaitAny(ShmReader* const* readers, int count, std::chrono::nanoseconds timeout,
                        std::chrono::nanoseconds spin, std::atomic<std::uint32_t>* extra,
                        std::uint32_t extra_expected) noexcept {
  if (count == 1 && extra == nullptr) return readers[0]->Wait(timeout, spin);
  using Clock = std::chrono::steady_clock;
  constexpr int kMax = 64;
  count = std::min(count, kMax);
  auto any = [&] {
    if (extra != nullptr && extra->load(std::memory_order_seq_cst) != extra_expected) return true;
    for (int i = 0; i < count; ++i) {
      if (readers[i]->Available()) return true;
    }
    return false;
  };
  const auto start = Clock::now();
  const auto deadline = start + timeout;
  const auto spin_until = start + std::min(spin, timeout);
  while (Clock::now() < spin_until) {
    if (any()) return true;
    EDSP_CPU_RELAX();
  }
  std::atomic<std::uint32_t>* bells[kMax + 1];
  std::uint32_t rung[kMax + 1];
  for (;;) {
    for (int i = 0; i < count; ++i) {
      bells[i] = &readers[i]->segment_->header()->doorbell;
      rung[i] = bells[i]->load(std::memory_order_seq_cst);
    }
    int words = count;
    if (extra != nullptr) {
      bells[words] = extra;
      rung[words++] = extra_expected;
    }
    if (any()) return true;
    const auto now = Clock::now();
    if (now >= deadline) return false;
    // The same handshake as Wait(), on every channel: announce, re-check, sleep.
    for (int i = 0; i < count; ++i) readers[i]->segment_->header()->sleepers.fetch_add(1, std::memory_order_seq_cst);
    const bool ready = any() || (FutexWaitAny(bells, rung, words, deadline - now), any());
    for (int i = 0; i < count; ++i) readers[i]->segment_->header()->sleepers.fetch_sub(1, std::memory_order_seq_cst);
    if (ready) return true;
  }
}

bool ShmReader::WriterAlive() const {
  const ShmSegmentHeader* h = segment_->header();
  return ProcessAlive(h->writer_pid.load(std::memory_order_acquire),
                      h->writer_start_ticks.load(std::memory_order_acquire));
}

bool ShmReader::WriterLeft() const noexcept {
  return segment_->header()->writer_pid.load(std::memory_order_acquire) == 0;
}

std::uint32_t ShmReader::writer_generation() const {
  return segment_->header()->writer_generation.load(std::memory_order_acquire);
}

}  // namespace edsp
