#pragma once
// The one door to the drives (ros2_control's SystemInterface, edsp-sized):
// configure → activate → read/write each cycle → deactivate → cleanup, and
// from a failed cycle to a fault that the operator's re-arm recovers from
// (backend_lifecycle.h has the table). The bridge never
// knows which backend is behind it; backends are siblings chosen by
// configuration ([drives] backend: the virtual rig's image, Modbus TCP).
//
// A cycle is one Read and then one Write, both at the cycle's start (a
// cyclic fieldbus master's fixed phases): commands only change what the next
// Write carries, so a master sees one exchange per period. The lifecycle
// calls (Configure, Activate, Reset, Deactivate) are acyclic, as a master's
// mailbox/SDO requests are: Reset runs on the operator's re-arm, between
// cycles, and may take several exchanges.

#include <array>
#include <cstdint>
#include <string>

#include "edsp/kinematics/config.h"
#include "edsp/node/runtime.h"

namespace edsp {

enum class BackendState { kUnconfigured, kInactive, kActive, kFault };

// Per-leg status, the values of leg_state_t's DRIVE_* constants.
enum class DriveStatus : std::int8_t { kDisabled = 0, kEnabled = 1, kHolding = 2, kFault = 3 };

struct DriveSetpoint {
  std::array<double, 6> motor_angle_rad{};       // position target, from home
  std::array<double, 6> motor_velocity_rad_s{};  // velocity feed-forward
  // The instant the target is for (the setpoint's utime), so a drive that
  // takes it later, at its own cycle's phase, continues it along the
  // velocity from there instead of lagging by that phase; 0: when it arrives.
  std::int64_t utime = 0;
};

struct DriveFeedback {
  std::array<double, 6> motor_angle_rad{};
  std::array<double, 6> motor_velocity_rad_s{};
  std::array<DriveStatus, 6> status{};
  // The instant the reading describes, when the drives say (the virtual
  // rig's image: its cycle's start); 0: not said, taken as the read's.
  std::int64_t utime = 0;
};

class DriveBackend {
 public:
  virtual ~DriveBackend() = default;
  // Set-up; false with *error saying why.
  virtual bool Configure(const PlatformConfig& config, std::string* error) = 0;
  virtual bool Activate(std::string* error) = 0;
  virtual void Deactivate() = 0;
  // Inactive → unconfigured: lets go of what Configure took (a link, a
  // segment). Backends that hold nothing have nothing to do.
  virtual void Cleanup() {}
  // Cyclic; never throw. Motion setpoints are accepted only while kActive.
  virtual bool Read(std::int64_t now_utime, DriveFeedback* feedback) = 0;
  virtual bool Write(std::int64_t now_utime, const DriveSetpoint& setpoint) = 0;
  virtual BackendState state() const = 0;
  // The operator's re-arm: drives that left operation (a fault, a quick
  // stop) are reset and enabled again where they stand, and a backend in
  // fault recovers (active again). Backends whose drives need nothing of
  // the kind have nothing to do.
  virtual bool Reset(std::string* /*error*/) { return true; }
  // Why the last cycle failed (which drive, its error), "" when unknown.
  virtual std::string Detail() const { return ""; }
  // A backend that owns the cycle's clock (an EtherCAT master whose
  // distributed clock sets the period) returns it, and the bridge's loop
  // ticks on it; null: the bridge's own clock on the host's grid.
  virtual CycleClock* Clock() { return nullptr; }
};

}  // namespace edsp
