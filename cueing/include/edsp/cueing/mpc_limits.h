#pragma once
// The box the model-predictive cueing keeps the platform in, per axis of
// its pose about the neutral one (x y z m, roll pitch yaw rad): position,
// velocity and acceleration, each channel's a share of what was wanted, so
// that any point of the channels' boxes keeps every leg inside its stroke,
// its speed and its acceleration limits at once (docs/cueing.md,
// "Model-predictive cueing"). The shares move between channels as their
// demand does; what a channel's plan holds stays its own.
//
// For leg i, l_i(q) − l_i(q0) ≤ Σ_j L_ij |q_j − q0_j| with L_ij the largest
// |∂l_i/∂q_j| over the wanted box (sampled at its 64 corners, its centre and
// random points, and widened by 5%), so channel c's axes at λ_c times
// their wanted b_j keep leg i in its stroke while
//   Σ_c λ_c Σ_{j in c} L_ij b_j ≤ (1 − margin) · room_i;
// the same with the legs' speed limit for the velocities, and for the
// accelerations after the part the velocities alone cause (q̇ᵀ ∇²l_i q̇, the
// largest over the velocities' largest box). The corners of the box with
// every channel at its largest share are checked against the joint angles
// and the Jacobian's conditioning, and the wanted position shrunk until
// they pass.

#include <array>
#include <string>

#include <Eigen/Core>

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

// The four channels that share the legs (cueing/mpc_cueing.h) and the axes
// (x y z roll pitch yaw) each moves: surge x and pitch, sway y and roll,
// heave z, yaw.
constexpr int kMpcChannels = 4;
using MpcChannelVector = Eigen::Matrix<double, kMpcChannels, 1>;
constexpr std::array<int, 6> kMpcChannelOfAxis = {0, 1, 2, 1, 0, 3};

// One kind of leg limit (the stroke for positions, the speed for
// velocities, the acceleration for accelerations) shared by the channels:
// with channel c's axes at λ_c times the wanted box, leg i keeps
// Σ_c λ_c use(c, i) ≤ budget(i).
struct MpcLegShare {
  Eigen::Matrix<double, kMpcChannels, 6> use = Eigen::Matrix<double, kMpcChannels, 6>::Zero();
  Vector6 budget = Vector6::Zero();
  MpcChannelVector most = MpcChannelVector::Zero();  // each channel's λ with the others at rest, ≤ 1

  // The λ of every channel: each keeps what it has committed (its plan's
  // largest share of the wanted box), and the legs' room left is given
  // out by demand (≥ 0; the most demanding channel may take all it can):
  //   λ_c = m_c + s d_c (most_c − m_c) / max d,  s ≤ 1 the largest every leg allows.
  MpcChannelVector Allocate(const MpcChannelVector& committed, const MpcChannelVector& demand) const;
  // Σ_c λ_c use(c, i) / budget(i), the most of any leg: ≤ 1 inside the limits.
  double Load(const MpcChannelVector& lambda) const;
};

// What the legs give the model-predictive cueing: the wanted box (its
// position shrunk until the corners of every channel's largest box at once
// keep the joint angles and the conditioning) and the three shares.
struct MpcLegRoom {
  MpcAxisLimits wanted;
  MpcLegShare position, velocity, acceleration;
  // The box of the channels at these λs (position, velocity, acceleration).
  MpcAxisLimits Box(const MpcChannelVector& position_lambda, const MpcChannelVector& velocity_lambda,
                    const MpcChannelVector& acceleration_lambda) const;
  // The box every channel may fill at once (each the same share of its largest).
  MpcAxisLimits AllAtOnce() const;
};

// Throws std::invalid_argument naming the axis of a wanted limit that is
// not finite or ≤ 0, a margin outside [0, 0.5], or a neutral pose outside
// the workspace.
MpcLegRoom DeriveMpcLegRoom(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
                            double margin);
// The box every channel may fill at once (MpcLegRoom::AllAtOnce): what no
// allocation takes a channel below. Throws as DeriveMpcLegRoom.
MpcAxisLimits DeriveMpcLimits(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
                              double margin);

}  // namespace edsp
