#pragma once
// Memory layout of one shared-memory channel segment: a header, then a ring
// of fixed-size slots. Shared between processes (and builds): any change here
// bumps kShmLayoutVersion.
//
//   [SegmentHeader][Slot 0: SlotHeader + payload][Slot 1] ... [Slot N-1]
//
// Message n (n = 1, 2, ...) lives in slot n mod N. Per-slot seqlock: the
// writer sets sequence = 2n−1 before touching the payload and 2n after; a
// reader that sees the same even value 2n before and after reading has an
// untorn copy of message n.

#include <atomic>
#include <cstdint>

namespace edsp {

inline constexpr std::uint64_t kShmMagic = 0x314D48535053'4445ull;  // "EDSPSHM1"
inline constexpr std::uint32_t kShmLayoutVersion = 1;
inline constexpr std::uint32_t kCacheLine = 64;
// Message numbers stay below this (sequence = 2n must not overflow).
inline constexpr std::uint64_t kShmMaxMessages = std::uint64_t{1} << 62;

struct alignas(kCacheLine) ShmSegmentHeader {
  // Immutable after initialisation; protected by `checksum`. `magic` is
  // stored last (release), so a reader never sees a half-built header.
  std::atomic<std::uint64_t> magic;
  std::uint32_t layout_version;
  std::uint32_t header_size_bytes;
  std::int64_t type_fingerprint;  // the LCM type's hash
  std::uint32_t slot_count;       // power of two
  std::uint32_t slot_size_bytes;  // payload capacity of one slot
  std::uint32_t slot_stride_bytes;
  std::uint32_t checksum;  // over the fields above, see ShmHeaderChecksum

  // Writer identity: pid and its start time (clock ticks since boot, from
  // /proc/<pid>/stat) so a recycled pid is not mistaken for a live writer.
  std::atomic<std::int32_t> writer_pid;
  std::atomic<std::uint64_t> writer_start_ticks;
  std::atomic<std::uint32_t> writer_generation;  // +1 at every writer attach

  alignas(kCacheLine) std::atomic<std::uint64_t> published;  // last complete message n
  alignas(kCacheLine) std::atomic<std::uint32_t> doorbell;   // futex word, +1 per message
  std::atomic<std::uint32_t> sleepers;                       // readers blocked on doorbell
};

struct alignas(kCacheLine) ShmSlotHeader {
  std::atomic<std::uint64_t> sequence;  // 2n−1 while writing message n, 2n when done
  std::uint32_t size_bytes;             // encoded size of message n
  std::uint32_t reserved;
  std::int64_t publish_utime;  // writer's clock at publish, microseconds
};

static_assert(sizeof(ShmSegmentHeader) % kCacheLine == 0);
static_assert(sizeof(ShmSlotHeader) == kCacheLine);
static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

// FNV-1a over the immutable header fields (and the expected magic), so the
// checksum can be written before `magic` publishes the header.
std::uint32_t ShmHeaderChecksum(const ShmSegmentHeader& header);

// Bytes one slot occupies: header + payload, rounded up to a cache line.
std::uint32_t ShmSlotStride(std::uint32_t slot_size_bytes);

// Whole segment size for the given geometry.
std::uint64_t ShmSegmentBytes(std::uint32_t slot_count, std::uint32_t slot_size_bytes);

}  // namespace edsp
