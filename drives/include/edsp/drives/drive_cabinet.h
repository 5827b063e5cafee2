#pragma once
// Six simulated CSP drives and the axes they move, cycled together: what a
// drive simulator serves over its fieldbus (modbus_drive_server.h), and what
// a test drives directly. A cycle runs each drive's timers, steps the axes
// on what every drive demands, then lets each drive sense its axis.

#include <array>
#include <cstdint>
#include <memory>

#include "edsp/drives/csp_axes.h"
#include "edsp/drives/simulated_csp_drive.h"

namespace edsp::cia402 {

class DriveCabinet {
 public:
  // Null `axes`: six bounded-speed axes at count 0 (options' speed).
  DriveCabinet(const SimulatedDriveOptions& options, std::unique_ptr<CspAxes> axes);

  // The master's write of all six drives' RxPDOs, arrived at `utime`.
  void Command(const std::array<CspCommand, kCabinetDrives>& commands, std::int64_t utime);
  void Tick(double dt_s);
  void InjectFault(int drive, std::uint16_t error_code);

  CspFeedback Feedback(int drive) const { return drives_[static_cast<std::size_t>(drive)].Feedback(); }
  State state(int drive) const { return drives_[static_cast<std::size_t>(drive)].state(); }

 private:
  std::array<SimulatedCspDrive, kCabinetDrives> drives_;
  std::unique_ptr<CspAxes> axes_;
  std::int64_t command_utime_ = 0;
};

}  // namespace edsp::cia402
