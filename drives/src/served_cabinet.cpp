#include "edsp/drives/served_cabinet.h"

namespace edsp::cia402 {

ServedCabinet::ServedCabinet(const SimulatedDriveOptions& options, std::unique_ptr<CspAxes> axes)
    : cabinet_(options, std::move(axes)) {
  for (auto& pending : pending_faults_) pending.store(0);
  // The drives' state before the first request, as a cycle latched it.
  Tick(0.0);
}

void ServedCabinet::InjectFault(int index, std::uint16_t error_code) {
  if (index >= 0 && index < kCabinetDrives) pending_faults_[static_cast<std::size_t>(index)].store(error_code);
}

bool ServedCabinet::Tick(double dt_s) {
  if (clock_stopped_.load()) return false;
  for (int d = 0; d < kCabinetDrives; ++d) {
    const std::uint16_t fault = pending_faults_[static_cast<std::size_t>(d)].exchange(0);
    if (fault != 0) cabinet_.InjectFault(d, fault);
  }
  cabinet_.Tick(dt_s);
  ++cycles_;
  for (int d = 0; d < kCabinetDrives; ++d) {
    CspFeedback& f = latched_[static_cast<std::size_t>(d)];
    f = cabinet_.Feedback(d);
    f.cycle_count = cycles_;
  }
  return true;
}

CycleSchedule::CycleSchedule(double cycle_s)
    : cycle_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(cycle_s))),
      next_tick_(Clock::now() + cycle_) {}

std::int64_t CycleSchedule::Due(Clock::time_point now) {
  if (now < next_tick_) return 0;
  const auto missed = (now - next_tick_) / cycle_ + 1;
  next_tick_ += cycle_ * missed;
  return static_cast<std::int64_t>(missed);
}

}  // namespace edsp::cia402
