#include "edsp/drives/csp_shm_server.h"

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "edsp/drives/csp_shm_image.h"

namespace edsp::cia402 {
namespace {

// Looking for an absent ring costs an exception inside Boost.Interprocess,
// and whether a silent master's process still runs a /proc lookup: both at
// this pace, not at the drives' 1 kHz.
constexpr std::int64_t kLookForMasterEveryUs = 10000;

}  // namespace

CspShmServer::CspShmServer(const ShmDriveServerOptions& options, std::unique_ptr<CspAxes> axes)
    : options_(options), cabinet_(options.drive, std::move(axes)) {
  if (!(options.cycle_s > 0.0 && options.cycle_s <= 0.1)) {
    throw std::runtime_error(fmt::format("drive cycle {} s: must be in (0, 0.1]", options.cycle_s));
  }
  auto writer = ShmWriter::Open(CspTxSpec(options.prefix, options.permissions));
  if (!writer.ok()) throw std::runtime_error(fmt::format("{}: {}", endpoint(), writer.message));
  feedback_ = std::move(writer.value);
  Latch();  // the drives' state before the master's first exchange
}

void CspShmServer::TakeCommands() {
  // The newest unread RxPDOs first, whether or not their master is still
  // there: written while it was (a bridge's last act, the Shutdown of its
  // deactivation, is followed at once by its exit).
  if (commands_ != nullptr) {
    commands_->SkipToLatest();
    CspRxImage image{};
    const TakeStatus status = commands_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
      if (size != sizeof image) return false;
      std::memcpy(&image, data, sizeof image);
      return true;
    });
    if (status == TakeStatus::kMessage) {
      CspCommands commands;
      for (std::size_t d = 0; d < commands.size(); ++d) commands[d] = image.drives[d];
      cabinet_.Command(commands, image.utime);  // the instant the master wrote them
      return;                                   // its master wrote it since the last cycle: no need to look for one
    }
  }
  const std::int64_t now = ImageUtimeNow();
  if (now < next_look_utime_) return;
  next_look_utime_ = now + kLookForMasterEveryUs;
  if (commands_ != nullptr && !commands_->WriterLeft() && commands_->WriterAlive()) return;
  // No master, or a new one (a restarted bridge's ring): a new reader starts
  // after the ring's newest record, so a dead master's last RxPDOs are
  // never taken as a command.
  auto reader = ShmReader::Open(CspRxSpec(options_.prefix, options_.permissions));
  commands_ = reader.ok() ? std::move(reader.value) : nullptr;
}

void CspShmServer::Latch() {
  CspTxImage image{};
  image.utime = ImageUtimeNow();
  for (std::size_t d = 0; d < cabinet_.latched().size(); ++d) image.drives[d] = cabinet_.latched()[d];
  feedback_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
    std::memcpy(buffer, &image, sizeof image);
    return sizeof image;
  });
}

void CspShmServer::Run(const std::function<bool()>& stop) {
  CycleSchedule schedule(options_.cycle_s);
  while (!stop()) {
    std::this_thread::sleep_until(schedule.next_tick());
    const std::int64_t due = schedule.Due(CycleSchedule::Clock::now());
    if (due == 0) continue;
    TakeCommands();
    if (cabinet_.Tick(options_.cycle_s * static_cast<double>(due))) Latch();
  }
}

}  // namespace edsp::cia402
