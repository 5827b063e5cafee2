#include "edsp/drives/drive_cabinet.h"

namespace edsp::cia402 {

DriveCabinet::DriveCabinet(const SimulatedDriveOptions& options, std::unique_ptr<CspAxes> axes)
    : drives_{SimulatedCspDrive(options), SimulatedCspDrive(options), SimulatedCspDrive(options),
              SimulatedCspDrive(options), SimulatedCspDrive(options), SimulatedCspDrive(options)},
      axes_(axes != nullptr ? std::move(axes) : std::make_unique<SimulatedAxes>(options.max_speed_counts_s, 0.0)) {
  Tick(0.0);  // each drive senses where its axis stands before any command
}

void DriveCabinet::Command(const std::array<CspCommand, kCabinetDrives>& commands, std::int64_t utime) {
  for (std::size_t d = 0; d < drives_.size(); ++d) drives_[d].Command(commands[d]);
  command_utime_ = utime;
}

void DriveCabinet::InjectFault(int drive, std::uint16_t error_code) {
  drives_[static_cast<std::size_t>(drive)].InjectFault(error_code);
}

void DriveCabinet::Tick(double dt_s) {
  std::array<AxisDemand, kCabinetDrives> demands;
  for (std::size_t d = 0; d < drives_.size(); ++d) {
    drives_[d].Advance(dt_s);
    demands[d] = drives_[d].Demand();
  }
  axes_->Step(dt_s, command_utime_, demands);
  for (std::size_t d = 0; d < drives_.size(); ++d) drives_[d].Sense(axes_->Reading(static_cast<int>(d)));
}

}  // namespace edsp::cia402
