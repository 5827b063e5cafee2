#pragma once
// The drives of a DriveBackend as the axes of CiA 402 drives: what
// edsp-drive-sim serves behind its six state machines when the virtual rig
// computes the drives' physics (the sim-modbus group: bridge → Modbus TCP →
// edsp-drive-sim → the rig's process image → edsp-rig). The gateway a drive
// vendor's CSP firmware is to its power stage.
//
// - A following drive's target (counts) goes to the backend as a motor angle
//   through the drive's [drives] scaling, its velocity offset as the
//   feed-forward, stamped with the instant the master wrote it.
// - A drive that does not follow (any state but operation enabled) holds its
//   leg where it stood when it stopped following (the brake), never at its
//   drifting actual. Nor does a drive follow a command older than its
//   fieldbus timeout, even before its watchdog has seen that time pass (the
//   simulator stopped in the middle of a cycle): it would have stopped then.
// - Where the legs stand comes back in counts. The backend's feedback
//   silent (the rig gone, frozen) or a leg the rig reports in fault is the
//   drive's own error: 7300h (position sensor) on every drive, 5000h on that
//   drive, so the master sees it through 603Fh as from real drives.

#include <array>
#include <memory>
#include <string>

#include "edsp/drive_io/drive_backend.h"
#include "edsp/drives/csp_axes.h"
#include "edsp/drives/csp_image.h"

namespace edsp::cia402 {

inline constexpr std::uint16_t kErrorPositionSensor = 0x7300;
inline constexpr std::uint16_t kErrorDeviceHardware = 0x5000;

class BackendAxes final : public CspAxes {
 public:
  // Configures and activates `backend` (waiting for its first feedback);
  // throws std::runtime_error saying why it cannot. `fieldbus_timeout_us`:
  // the drives' (a command older than this is not followed).
  BackendAxes(std::unique_ptr<DriveBackend> backend, const PlatformConfig& config,
              const std::array<DriveScaling, kCabinetDrives>& scaling, std::int64_t fieldbus_timeout_us);
  ~BackendAxes() override;
  BackendAxes(const BackendAxes&) = delete;
  BackendAxes& operator=(const BackendAxes&) = delete;

  void Step(double dt_s, std::int64_t command_utime, const std::array<AxisDemand, kCabinetDrives>& demands) override;
  AxisReading Reading(int drive) const override { return readings_[static_cast<std::size_t>(drive)]; }

 private:
  void Sense(std::int64_t now_utime);
  DriveSetpoint Actuate(std::int64_t now_utime, std::int64_t command_utime,
                        const std::array<AxisDemand, kCabinetDrives>& demands);

  std::unique_ptr<DriveBackend> backend_;
  std::array<DriveScaling, kCabinetDrives> scaling_;
  std::int64_t fieldbus_timeout_us_;
  DriveFeedback feedback_;
  bool feedback_ok_ = false;
  std::array<bool, kCabinetDrives> followed_{};    // last cycle
  std::array<double, kCabinetDrives> held_rad_{};  // where a standing drive holds
  std::array<AxisReading, kCabinetDrives> readings_{};
};

}  // namespace edsp::cia402
