#pragma once
// What a rig's drives can carry: the payload (platform included) whose
// weight the motors hold at every pose of the workspace with a share of
// their torque to spare for accelerating it. Within the rating the virtual
// rig's drives never reach their following-error window on the planner's
// motions; beyond it a drive may fault and brake (virtual_rig.h).

#include "edsp/kinematics/platform_model.h"
#include "edsp/rig/rig_effects.h"

namespace edsp {

struct PayloadRating {
  double payload_kg = 0.0;          // the rating
  double worst_force_per_kg = 0.0;  // N of leg force per kg at the worst pose sampled
  Pose worst_pose;                  //   that pose
};

// Share of the motors' torque the platform's weight may take; the rest is
// for acceleration and friction.
inline constexpr double kRatedTorqueShare = 2.0 / 3.0;

// Samples `poses` poses inside the workspace (config limits, a fixed seed:
// the same rating every time) within the box the preset's motions reach
// (±0.5 m across, ±0.3 m up and down, ±30°), its centre of mass at `com_M_m`.
PayloadRating RatePayload(const PlatformModel& model, const RigEffects::ServoLag& drives, const Vector3& com_M_m,
                          int poses = 4000);

}  // namespace edsp
