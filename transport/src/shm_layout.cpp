#include "edsp/transport/shm_layout.h"

#include <cstring>

namespace edsp {

namespace {

void Mix(std::uint32_t* hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    *hash ^= bytes[i];
    *hash *= 16777619u;
  }
}

}  // namespace

std::uint32_t ShmHeaderChecksum(const ShmSegmentHeader& h) {
  // The magic is checked on its own and is published last (it marks the
  // header complete), so the checksum covers the constant, not the field.
  std::uint32_t hash = 2166136261u;
  const std::uint64_t magic = kShmMagic;
  Mix(&hash, &magic, sizeof magic);
  Mix(&hash, &h.layout_version, sizeof h.layout_version);
  Mix(&hash, &h.header_size_bytes, sizeof h.header_size_bytes);
  Mix(&hash, &h.type_fingerprint, sizeof h.type_fingerprint);
  Mix(&hash, &h.slot_count, sizeof h.slot_count);
  Mix(&hash, &h.slot_size_bytes, sizeof h.slot_size_bytes);
  Mix(&hash, &h.slot_stride_bytes, sizeof h.slot_stride_bytes);
  return hash;
}

std::uint32_t ShmSlotStride(std::uint32_t slot_size_bytes) {
  const std::uint64_t raw = sizeof(ShmSlotHeader) + std::uint64_t{slot_size_bytes};
  return static_cast<std::uint32_t>((raw + kCacheLine - 1) / kCacheLine * kCacheLine);
}

std::uint64_t ShmSegmentBytes(std::uint32_t slot_count, std::uint32_t slot_size_bytes) {
  return sizeof(ShmSegmentHeader) + std::uint64_t{slot_count} * ShmSlotStride(slot_size_bytes);
}

}  // namespace edsp
