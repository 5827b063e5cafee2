#pragma once
// What the drives are told while the leg commands are late and the bridge
// itself is on time (a planner or kinematics tick missed on a loaded host):
// the last command's motion, continued along its velocity feed-forward for
// timing::kRideThroughUs (a loaded host's stalls are mostly shorter), then
// brought to rest with every leg decelerating in proportion, the fastest at
// the legs' acceleration limit, so the platform stops along its path. A
// stream that comes back within it finds the drives where it would
// have put them; holding the last command's position would pull them back
// by the distance already continued and send them forward again when the
// stream came back (test ControllerStall.*; its figures in docs/figures.md).

#include <cstdint>

#include "edsp/drive_io/drive_backend.h"
#include "edsp/timing_contract.h"

namespace edsp {

struct RideThrough {
  double continue_s = timing::kRideThroughS;  // along the feed-forward, before the ramp
  double stop_s = 0.0;                        // the ramp's length: the fastest leg's speed / its deceleration
};

// The ramp's length for `command`: its fastest leg (`leg_m_per_rad` of leg
// per motor radian) brought to rest at `decel_m_s2`.
double StopTimeS(const DriveSetpoint& command, double leg_m_per_rad, double decel_m_s2);

// The setpoint `silent_s` after `command` was taken, stamped at that instant
// of the command's own clock (command.utime + silent_s): on the profile
// above, its velocity the profile's slope there.
DriveSetpoint RideThroughSetpoint(const DriveSetpoint& command, const RideThrough& ride, double silent_s);

}  // namespace edsp
