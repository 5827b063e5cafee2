#pragma once
// A shared-memory channel segment (Boost.Interprocess shared_memory_object +
// mapped_region), validated on attach. Move-only: whoever holds it owns the
// mapping. Factories return an expected-like ShmResult, never throw.

#include <sys/types.h>

#include <memory>
#include <string>

#include "edsp/transport/shm_layout.h"

namespace edsp {

// What a channel's segment must look like.
struct ShmChannelSpec {
  std::string segment_name;  // e.g. "edsp.EDSP_LEG_COMMAND" (in /dev/shm)
  std::int64_t type_fingerprint = 0;
  std::uint32_t slot_count = 64;         // power of two, 2..65536
  std::uint32_t slot_size_bytes = 4096;  // largest encoded message, ≤ 16 MiB
  mode_t permissions = 0600;             // the segment file's mode
  // A reader that copies bytes and never decodes them (the logger): takes
  // whatever type the segment carries. A writer always names its type.
  bool any_type = false;
};

enum class ShmError {
  kNone,
  kBadSpec,           // slot count/size out of range or not a power of two
  kNotFound,          // no segment yet (reader before writer)
  kNotReady,          // a writer is still initialising it
  kCorruptHeader,     // bad magic, checksum or size: not an edsp segment
  kLayoutVersion,     // made by another edsp layout version
  kTypeMismatch,      // another LCM type (fingerprint) on this channel
  kGeometryMismatch,  // other slot count or slot size
  kWriterAlive,       // another live process is this channel's writer
  kSystem,            // shm_open/ftruncate/mmap failed
};

const char* ShmErrorName(ShmError error);

class ShmSegment {
 public:
  struct Mapping;  // opaque: the Boost.Interprocess object and region
  ShmSegment(ShmSegment&&) noexcept;
  ShmSegment& operator=(ShmSegment&&) noexcept;
  ShmSegment(const ShmSegment&) = delete;
  ShmSegment& operator=(const ShmSegment&) = delete;
  ~ShmSegment();

  ShmSegmentHeader* header() const { return header_; }
  ShmSlotHeader* slot(std::uint64_t message_number) const;
  std::uint8_t* payload(ShmSlotHeader* slot) const {
    return reinterpret_cast<std::uint8_t*>(slot) + sizeof(ShmSlotHeader);
  }
  const std::string& name() const { return name_; }

 private:
  friend struct ShmSegmentFactory;
  ShmSegment(std::string name, std::unique_ptr<Mapping> mapping);

  std::string name_;
  std::unique_ptr<Mapping> mapping_;
  ShmSegmentHeader* header_ = nullptr;
  std::uint8_t* slots_ = nullptr;
  std::uint64_t slot_mask_ = 0;
  std::uint32_t stride_ = 0;
};

template <typename T>
struct ShmResult {
  std::unique_ptr<T> value;  // set on success
  ShmError error = ShmError::kNone;
  std::string message;  // names the segment and what is wrong
  bool ok() const { return error == ShmError::kNone; }
};

// For the channel's writer: attaches to a compatible segment whose writer is
// dead (a restart after a crash: readers keep going), reclaims an
// incompatible one whose writer is dead, creates one if none exists. Claims
// the writer role; fails with kWriterAlive if a live process holds it.
ShmResult<ShmSegment> AttachSegmentAsWriter(const ShmChannelSpec& spec);

// For a reader: the existing segment, validated against the spec.
ShmResult<ShmSegment> AttachSegmentAsReader(const ShmChannelSpec& spec);

// Removes the segment name (mappings stay valid until unmapped).
void RemoveSegment(const std::string& segment_name);

// The calling process's identity as stored in the header.
std::int32_t CurrentPid();
std::uint64_t ProcessStartTicks(std::int32_t pid);  // 0 if no such process
bool ProcessAlive(std::int32_t pid, std::uint64_t start_ticks);

}  // namespace edsp
