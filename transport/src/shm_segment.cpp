#include "edsp/transport/shm_segment.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>
#include <sstream>
#include <thread>

#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <fmt/format.h>

namespace edsp {

namespace bip = boost::interprocess;

const char* ShmErrorName(ShmError error) {
  switch (error) {
    case ShmError::kNone: return "ok";
    case ShmError::kBadSpec: return "bad channel spec";
    case ShmError::kNotFound: return "segment not found";
    case ShmError::kNotReady: return "segment not ready";
    case ShmError::kCorruptHeader: return "corrupt segment header";
    case ShmError::kLayoutVersion: return "layout version mismatch";
    case ShmError::kTypeMismatch: return "message type mismatch";
    case ShmError::kGeometryMismatch: return "slot geometry mismatch";
    case ShmError::kWriterAlive: return "another writer is alive";
    case ShmError::kSystem: return "system error";
  }
  return "unknown error";
}

struct ShmSegment::Mapping {
  bip::shared_memory_object object;
  bip::mapped_region region;
};

ShmSegment::ShmSegment(std::string name, std::unique_ptr<Mapping> mapping)
    : name_(std::move(name)), mapping_(std::move(mapping)) {
  auto* base = static_cast<std::uint8_t*>(mapping_->region.get_address());
  header_ = reinterpret_cast<ShmSegmentHeader*>(base);
  slots_ = base + sizeof(ShmSegmentHeader);
  slot_mask_ = header_->slot_count - 1;
  stride_ = header_->slot_stride_bytes;
}

ShmSegment::ShmSegment(ShmSegment&&) noexcept = default;
ShmSegment& ShmSegment::operator=(ShmSegment&&) noexcept = default;
ShmSegment::~ShmSegment() = default;

ShmSlotHeader* ShmSegment::slot(std::uint64_t message_number) const {
  return reinterpret_cast<ShmSlotHeader*>(slots_ + (message_number & slot_mask_) * stride_);
}

// Builds segments; a friend so the constructor stays private.
struct ShmSegmentFactory {
  static std::unique_ptr<ShmSegment> Make(const std::string& name, std::unique_ptr<ShmSegment::Mapping> mapping) {
    return std::unique_ptr<ShmSegment>(new ShmSegment(name, std::move(mapping)));
  }
};

std::int32_t CurrentPid() { return static_cast<std::int32_t>(::getpid()); }

std::uint64_t ProcessStartTicks(std::int32_t pid) {
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text;
  if (!std::getline(stat, text)) return 0;
  // Field 2 (comm) may hold spaces and parentheses: count from the last ')'.
  const std::size_t close = text.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 22 && (fields >> field); ++i) {
    if (i == 22) return std::stoull(field);
  }
  return 0;
}

bool ProcessAlive(std::int32_t pid, std::uint64_t start_ticks) {
  if (pid <= 0) return false;
  if (::kill(pid, 0) != 0 && errno != EPERM) return false;
  const std::uint64_t now = ProcessStartTicks(pid);
  // A zombie or a recycled pid has another (or no) start time.
  return now != 0 && now == start_ticks;
}

namespace {

ShmResult<ShmSegment> Fail(ShmError error, std::string message) {
  ShmResult<ShmSegment> result;
  result.error = error;
  result.message = std::move(message);
  return result;
}

bool IsPowerOfTwo(std::uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

ShmResult<ShmSegment> CheckSpec(const ShmChannelSpec& spec) {
  if (spec.segment_name.empty() || spec.segment_name.find('/') != std::string::npos) {
    return Fail(ShmError::kBadSpec,
                fmt::format("segment name \"{}\" must be non-empty without '/'", spec.segment_name));
  }
  if (!IsPowerOfTwo(spec.slot_count) || spec.slot_count < 2 || spec.slot_count > 65536) {
    return Fail(ShmError::kBadSpec, fmt::format("{}: slot count {} must be a power of two in "
                                                "2..65536",
                                                spec.segment_name, spec.slot_count));
  }
  if (spec.slot_size_bytes == 0 || spec.slot_size_bytes > (16u << 20)) {
    return Fail(ShmError::kBadSpec,
                fmt::format("{}: slot size {} bytes must be in 1..16 MiB", spec.segment_name, spec.slot_size_bytes));
  }
  return {};
}

// Checks a mapped header. `check_geometry` (a writer's check): the spec's
// slot geometry is required; readers adopt the writer's.
ShmResult<ShmSegment> Validate(const ShmSegmentHeader& h, std::uint64_t mapped_bytes, const ShmChannelSpec& spec,
                               bool check_geometry) {
  const std::string& name = spec.segment_name;
  if (mapped_bytes < sizeof(ShmSegmentHeader)) {
    return Fail(ShmError::kCorruptHeader,
                fmt::format("{}: {} bytes is too small for an edsp segment", name, mapped_bytes));
  }
  const std::uint64_t magic = h.magic.load(std::memory_order_acquire);
  if (magic == 0) {
    return Fail(ShmError::kNotReady, fmt::format("{}: writer still initialising", name));
  }
  if (magic != kShmMagic) {
    return Fail(ShmError::kCorruptHeader, fmt::format("{}: bad magic {:#x}, not an edsp segment", name, magic));
  }
  if (h.checksum != ShmHeaderChecksum(h)) {
    return Fail(ShmError::kCorruptHeader, fmt::format("{}: header checksum mismatch", name));
  }
  if (h.layout_version != kShmLayoutVersion) {
    return Fail(ShmError::kLayoutVersion,
                fmt::format("{}: layout version {}, this build reads {}", name, h.layout_version, kShmLayoutVersion));
  }
  if (h.header_size_bytes != sizeof(ShmSegmentHeader) || !IsPowerOfTwo(h.slot_count) ||
      h.slot_stride_bytes != ShmSlotStride(h.slot_size_bytes) ||
      mapped_bytes < ShmSegmentBytes(h.slot_count, h.slot_size_bytes)) {
    return Fail(ShmError::kCorruptHeader,
                fmt::format("{}: header geometry inconsistent with its {} bytes", name, mapped_bytes));
  }
  const bool reader_takes_any_type = spec.any_type && !check_geometry;
  if (h.type_fingerprint != spec.type_fingerprint && !reader_takes_any_type) {
    return Fail(ShmError::kTypeMismatch, fmt::format("{}: carries type fingerprint {:#x}, expected {:#x}", name,
                                                     static_cast<std::uint64_t>(h.type_fingerprint),
                                                     static_cast<std::uint64_t>(spec.type_fingerprint)));
  }
  if (check_geometry && (h.slot_count != spec.slot_count || h.slot_size_bytes != spec.slot_size_bytes)) {
    return Fail(ShmError::kGeometryMismatch,
                fmt::format("{}: has {} slots of {} bytes, spec wants {} of {}", name, h.slot_count, h.slot_size_bytes,
                            spec.slot_count, spec.slot_size_bytes));
  }
  return {};
}

std::unique_ptr<ShmSegment::Mapping> MapExisting(const std::string& name, std::uint64_t* bytes) {
  auto mapping = std::make_unique<ShmSegment::Mapping>();
  mapping->object = bip::shared_memory_object(bip::open_only, name.c_str(), bip::read_write);
  bip::offset_t size = 0;
  mapping->object.get_size(size);
  *bytes = static_cast<std::uint64_t>(size);
  if (size > 0) mapping->region = bip::mapped_region(mapping->object, bip::read_write);
  return mapping;
}

void ClaimWriter(ShmSegmentHeader* h) {
  h->writer_start_ticks.store(ProcessStartTicks(CurrentPid()), std::memory_order_relaxed);
  h->writer_pid.store(CurrentPid(), std::memory_order_release);
  h->writer_generation.fetch_add(1, std::memory_order_acq_rel);
}

ShmResult<ShmSegment> CreateSegment(const ShmChannelSpec& spec) {
  auto mapping = std::make_unique<ShmSegment::Mapping>();
  mapping->object = bip::shared_memory_object(bip::create_only, spec.segment_name.c_str(), bip::read_write,
                                              bip::permissions(spec.permissions));
  // shm_open applies the umask; the configured mode is the contract.
  ::fchmod(mapping->object.get_mapping_handle().handle, spec.permissions);
  const std::uint64_t bytes = ShmSegmentBytes(spec.slot_count, spec.slot_size_bytes);
  mapping->object.truncate(static_cast<bip::offset_t>(bytes));
  mapping->region = bip::mapped_region(mapping->object, bip::read_write);
  auto* h = new (mapping->region.get_address()) ShmSegmentHeader{};  // pages are zero
  h->layout_version = kShmLayoutVersion;
  h->header_size_bytes = sizeof(ShmSegmentHeader);
  h->type_fingerprint = spec.type_fingerprint;
  h->slot_count = spec.slot_count;
  h->slot_size_bytes = spec.slot_size_bytes;
  h->slot_stride_bytes = ShmSlotStride(spec.slot_size_bytes);
  ClaimWriter(h);
  h->checksum = ShmHeaderChecksum(*h);
  // Publish last, with release: a reader (or a second writer) that sees the
  // magic sees a complete header; before it, only "not ready" (magic == 0).
  h->magic.store(kShmMagic, std::memory_order_release);
  ShmResult<ShmSegment> result;
  result.value = ShmSegmentFactory::Make(spec.segment_name, std::move(mapping));
  return result;
}

bool OwnerAlive(const ShmSegmentHeader& h) {
  return ProcessAlive(h.writer_pid.load(std::memory_order_acquire),
                      h.writer_start_ticks.load(std::memory_order_acquire));
}

}  // namespace

ShmResult<ShmSegment> AttachSegmentAsWriter(const ShmChannelSpec& spec) {
  if (auto bad = CheckSpec(spec); !bad.ok()) return bad;
  if (spec.any_type) {
    return Fail(
        ShmError::kBadSpec,
        fmt::format("{}: a writer must name its type (any_type is for readers that never decode)", spec.segment_name));
  }
  const std::string& name = spec.segment_name;
  for (int attempt = 0; attempt < 50; ++attempt) {
    try {
      std::uint64_t bytes = 0;
      auto mapping = MapExisting(name, &bytes);
      if (bytes < sizeof(ShmSegmentHeader)) {  // a creator died before truncating
        RemoveSegment(name);
        continue;
      }
      const auto* h = static_cast<const ShmSegmentHeader*>(mapping->region.get_address());
      ShmResult<ShmSegment> check = Validate(*h, bytes, spec, true);
      const bool alive = OwnerAlive(*h) && h->writer_pid.load() != CurrentPid();
      if (check.ok()) {
        if (alive) {
          return Fail(ShmError::kWriterAlive,
                      fmt::format("{}: process {} is already its writer", name, h->writer_pid.load()));
        }
        ShmResult<ShmSegment> result;
        result.value = ShmSegmentFactory::Make(name, std::move(mapping));
        ClaimWriter(result.value->header());  // a restart: readers keep going
        return result;
      }
      if (check.error == ShmError::kNotReady && alive) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        continue;
      }
      if (alive && check.error != ShmError::kCorruptHeader) {
        check.message += fmt::format(" (its writer, process {}, is alive)", h->writer_pid.load());
        return check;
      }
      RemoveSegment(name);  // stale: its writer is dead; reclaim it
    } catch (const bip::interprocess_exception& e) {
      if (e.get_error_code() != bip::not_found_error) {
        return Fail(ShmError::kSystem, fmt::format("{}: {}", name, e.what()));
      }
      try {
        return CreateSegment(spec);
      } catch (const bip::interprocess_exception& create_error) {
        if (create_error.get_error_code() != bip::already_exists_error) {
          return Fail(ShmError::kSystem, fmt::format("{}: {}", name, create_error.what()));
        }
        // Another process created it first: look again.
      }
    }
  }
  return Fail(ShmError::kNotReady, fmt::format("{}: could not claim the segment", name));
}

ShmResult<ShmSegment> AttachSegmentAsReader(const ShmChannelSpec& spec) {
  try {
    std::uint64_t bytes = 0;
    auto mapping = MapExisting(spec.segment_name, &bytes);
    if (bytes < sizeof(ShmSegmentHeader)) {
      return Fail(ShmError::kNotReady, fmt::format("{}: writer still initialising", spec.segment_name));
    }
    const auto* h = static_cast<const ShmSegmentHeader*>(mapping->region.get_address());
    ShmResult<ShmSegment> check = Validate(*h, bytes, spec, false);
    if (!check.ok()) return check;
    ShmResult<ShmSegment> result;
    result.value = ShmSegmentFactory::Make(spec.segment_name, std::move(mapping));
    return result;
  } catch (const bip::interprocess_exception& e) {
    if (e.get_error_code() == bip::not_found_error) {
      return Fail(ShmError::kNotFound, fmt::format("{}: no such segment (no writer yet?)", spec.segment_name));
    }
    return Fail(ShmError::kSystem, fmt::format("{}: {}", spec.segment_name, e.what()));
  }
}

void RemoveSegment(const std::string& segment_name) { bip::shared_memory_object::remove(segment_name.c_str()); }

}  // namespace edsp
