#include "edsp/drives/csp_shm_master.h"

#include <chrono>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "edsp/drives/csp_shm_image.h"

namespace edsp::cia402 {
namespace {

std::int64_t SteadyUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A new image proves the drives' side alive; without one, a side that
// closed its ring is seen at once, and whether a killed one's process
// still runs is looked up (in /proc, tens of µs) at this pace.
constexpr std::int64_t kAliveCheckEveryUs = 10000;

}  // namespace

CspShmMaster::CspShmMaster(std::string prefix, mode_t permissions, double response_timeout_s)
    : prefix_(std::move(prefix)),
      permissions_(permissions),
      response_timeout_us_(std::llround(response_timeout_s * 1e6)) {}

bool CspShmMaster::Connect(std::string* error) {
  Disconnect();
  if (commands_ == nullptr) {
    auto writer = ShmWriter::Open(CspRxSpec(prefix_, permissions_));
    if (!writer.ok()) {
      *error = fmt::format("{}: {}", endpoint(), writer.message);
      return false;
    }
    commands_ = std::move(writer.value);
  }
  const ShmChannelSpec spec = CspTxSpec(prefix_, permissions_);
  auto reader = ShmReader::Open(spec);
  if (!reader.ok()) {
    const bool absent = reader.error == ShmError::kNotFound || reader.error == ShmError::kNotReady;
    *error = fmt::format(
        "{}: {}", endpoint(),
        absent ? "no drives serve " + spec.segment_name + " (is edsp-drive-sim --serve shm running?)" : reader.message);
    return false;
  }
  if (!reader.value->WriterAlive()) {
    *error = fmt::format("{}: the drives' side of {} is gone (its process ended)", endpoint(), spec.segment_name);
    return false;
  }
  // An image the drives latch after this master attached (a new reader
  // starts past the ring's newest): what a frozen side left there is no
  // answer. None within the response timeout: they are not cycling.
  if (!reader.value->Wait(std::chrono::microseconds(response_timeout_us_))) {
    *error = fmt::format("{}: the drives latched nothing on {} within the response timeout ({:.1f} ms)", endpoint(),
                         spec.segment_name, static_cast<double>(response_timeout_us_) * 1e-3);
    return false;
  }
  feedback_ = std::move(reader.value);
  has_image_ = false;
  silence_.Heard(SteadyUs());
  CspFeedbacks first;
  return TakeLatest(&first, error);
}

bool CspShmMaster::Fail(const std::string& why, std::string* error) {
  *error = why;
  Disconnect();
  return false;
}

bool CspShmMaster::DrivesLeft(std::string* error) {
  return Fail(fmt::format("{}: the drives' side left {} (its process ended)", endpoint(), feedback_->segment().name()),
              error);
}

bool CspShmMaster::TakeLatest(CspFeedbacks* feedback, std::string* error) {
  if (!connected()) return Fail(endpoint() + ": not connected", error);
  if (feedback_->WriterLeft()) return DrivesLeft(error);  // its last image is no answer
  feedback_->SkipToLatest();
  CspTxImage image{};
  const TakeStatus status = feedback_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
    if (size != sizeof image) return false;
    std::memcpy(&image, data, sizeof image);
    return true;
  });
  const std::int64_t now = SteadyUs();
  if (status == TakeStatus::kDecodeError) {
    return Fail(fmt::format("{}: a TxPDO record that is not {} bytes", endpoint(), sizeof image), error);
  }
  if (status == TakeStatus::kMessage) {
    for (std::size_t d = 0; d < last_.size(); ++d) last_[d] = image.drives[d];
    silence_.Heard(now);
    has_image_ = true;
    *feedback = last_;
    return true;
  }
  if (!has_image_) return Fail(endpoint() + ": no image from the drives since connecting", error);
  if (now >= next_alive_check_utime_) {
    next_alive_check_utime_ = now + kAliveCheckEveryUs;
    if (!feedback_->WriterAlive()) return DrivesLeft(error);
  }
  // This master's own pauses are not the drives' silence.
  if (silence_.Missed(now) > response_timeout_us_) {
    if (!feedback_->WriterAlive()) return DrivesLeft(error);  // killed, rather than silent
    return Fail(fmt::format("{}: the drives latched nothing through {:.1f} ms of this master's exchanges (response "
                            "timeout {:.1f} ms): they are silent",
                            endpoint(), static_cast<double>(silence_.silent_us()) * 1e-3,
                            static_cast<double>(response_timeout_us_) * 1e-3),
                error);
  }
  *feedback = last_;
  return true;
}

bool CspShmMaster::Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error) {
  if (!connected()) return Fail(endpoint() + ": not connected", error);
  CspRxImage image{};
  image.utime = ImageUtimeNow();
  image.cycle = ++cycle_;
  for (std::size_t d = 0; d < commands.size(); ++d) image.drives[d] = commands[d];
  commands_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
    std::memcpy(buffer, &image, sizeof image);
    return sizeof image;
  });
  return TakeLatest(feedback, error);
}

bool CspShmMaster::ReadFeedback(CspFeedbacks* feedback, std::string* error) { return TakeLatest(feedback, error); }

}  // namespace edsp::cia402
