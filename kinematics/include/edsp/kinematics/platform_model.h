#pragma once
// PlatformModel: a validated config plus what every query needs precomputed
// (home leg lengths, home twists). Inverse kinematics, PR, compensation and
// forward kinematics are const member functions: no allocation, no throw,
// safe to call from a control loop.

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/passive_rotation.h"
#include "edsp/kinematics/pose.h"

namespace edsp {

// Everything inverse kinematics knows about the legs at one pose.
struct LegSolution {
  Matrix3 R_BM;
  Matrix36 r_MoPi_B;  // R_BM · p_MoPi_M: platform joint from {M}'s origin, in {B}
  Matrix36 leg_B;     // base joint → platform joint, Eq. (1)
  Vector6 length_m;   // Eq. (4)
  Matrix36 u_B;       // unit leg axes
  Matrix36 jd_B;      // platform outer axes in {B}, Eq. (6)
  Vector6 twist_rad;  // signed twist, passive_rotation.h
};

class PlatformModel {
 public:
  explicit PlatformModel(PlatformConfig config);

  const PlatformConfig& config() const { return config_; }
  const Pose& home_pose() const { return home_pose_; }
  const Vector6& home_length_m() const { return home_length_m_; }
  const Vector6& home_twist_rad() const { return home_twist_rad_; }

  // Eqs. (1)-(4) plus the signed twist of every leg.
  LegSolution Solve(const Pose& X_BM) const;
  Vector6 LegLengths(const Pose& X_BM) const;

  // ∂length/∂q with q = [x y z roll pitch yaw] (rpy rates, not ω).
  Matrix6 LengthJacobian(const Pose& X_BM) const;
  // Geometric Jacobian: length rates from the platform twist [v_B; ω_B];
  // row i = [u_iᵀ, (R·p_i × u_i)ᵀ].
  Matrix6 TwistJacobian(const Pose& X_BM) const;

  // PR length error (actual − encoder-implied) that `mode` predicts at the pose.
  Vector6 PrLengthError(const LegSolution& legs, PrMode mode) const;
  Vector6 PrLengthError(const Pose& X_BM, PrMode mode) const;
  // ∂(true signed PR length error)/∂q, analytic.
  Matrix6 PrLengthErrorJacobian(const Pose& X_BM) const;

  // Both Jacobians from one leg solution `legs` at X_BM, in one pass (what
  // forward kinematics needs every iteration). `pr_jacobian` may be null.
  void Jacobians(const Pose& X_BM, const LegSolution& legs, Matrix6* length_jacobian, Matrix6* pr_jacobian) const;

  // Eqs. (11)-(12): the leg lengths to command so that, with the PR `mode`
  // predicts, the platform reaches X_BM: IK length − PR length error.
  Vector6 CompensatedLengths(const Pose& X_BM, PrMode mode) const;

  // Encoder-implied lengths at which a platform whose screws follow the true
  // signed PR sits at X_BM (the rig's and forward kinematics' view).
  Vector6 EncoderLengths(const Pose& X_BM) const;

  // Observation point A in {B} at the pose.
  Vector3 ObservationPoint(const Pose& X_BM) const;

  // Drive conversions (motor angle 0 = home): what a length in encoder units
  // means as a motor angle, and back. lead/2π per screw turn, gear_ratio
  // motor turns per screw turn.
  double MotorAngleFromLength(int leg, double length_m) const;
  double LengthFromMotorAngle(int leg, double motor_angle_rad) const;

 private:
  double PrScale() const;  // s · lead / 2π

  PlatformConfig config_;
  Pose home_pose_;
  Vector6 home_length_m_;
  Vector6 home_twist_rad_;
};

}  // namespace edsp
