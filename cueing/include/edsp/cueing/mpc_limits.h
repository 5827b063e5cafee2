#pragma once
// The box the model-predictive cueing keeps the platform in, per axis of
// its pose about the neutral one (x y z m, roll pitch yaw rad): position,
// velocity and acceleration, each a share of what was wanted, so that any
// point of the box keeps every leg inside its stroke, its speed and its
// acceleration limits at once (docs/cueing.md, "Model-predictive cueing").
//
// For leg i, l_i(q) − l_i(q0) ≤ Σ_j L_ij |q_j − q0_j| with L_ij the largest
// |∂l_i/∂q_j| over the wanted box (sampled at its 64 corners, its centre and
// random points, and widened by 5%), so the box scaled by
//   λ = min(1, (1 − margin) · room_i / Σ_j L_ij b_j)
// keeps leg i in its stroke; the same with the legs' speed limit for the
// velocities, and for the accelerations after the part the velocities
// alone cause (q̇ᵀ ∇²l_i q̇, the largest over the box's corners). The
// box's corners are then checked against the joint angles and the
// Jacobian's conditioning, and the box shrunk until they pass.

#include <string>

#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct MpcAxisLimits {
  Vector6 position = Vector6::Zero();      // ± about the neutral pose
  Vector6 velocity = Vector6::Zero();      // ±, per axis
  Vector6 acceleration = Vector6::Zero();  // ±, per axis
  double position_scale = 1.0;             // the λ of each: the share of what was wanted
  double velocity_scale = 1.0;
  double acceleration_scale = 1.0;
  // "x ±0.101 m, …": for the config's errors and the bench.
  std::string Describe() const;
};

// Throws std::invalid_argument naming the axis of a wanted limit that is
// not finite or ≤ 0, a margin outside [0, 0.5], or a neutral pose outside
// the workspace.
MpcAxisLimits DeriveMpcLimits(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
                              double margin);

}  // namespace edsp
