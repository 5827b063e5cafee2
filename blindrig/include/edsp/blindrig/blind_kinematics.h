#pragma once
// The second rig's kinematics, written apart from kinematics/ on purpose: it
// is the independent truth edsp's model and diagnosis are scored against, so
// a bug in edsp's formulation shows up as a gap instead of cancelling out.
// Rotations come from Eigen's AngleAxis; each Hooke's joint is solved for its
// two explicit joint angles, the leg bodies' frames built from them, and the
// twist read between those frames; forward kinematics is Newton's method on a
// finite-difference Jacobian. Only the config's numbers are shared with edsp.

#include <Eigen/Core>
#include <Eigen/LU>

namespace edsp::blind {

inline constexpr double kPi = 3.14159265358979323846;

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat36 = Eigen::Matrix<double, 3, 6>;

struct BlindGeometry {
  Mat36 base_joint = Mat36::Zero();      // in {B}, m
  Mat36 platform_joint = Mat36::Zero();  // in {M}, m
  Mat36 base_axis = Mat36::Zero();       // outer axis fixed in {B}
  Mat36 platform_axis = Mat36::Zero();   // outer axis fixed in {M}
  double home_height_m = 0.0;
  Vec3 point_M = Vec3::Zero();  // observation point A in {M}
};

// q = [x y z roll pitch yaw]; R = Rz(yaw)·Ry(pitch)·Rx(roll).
Mat3 Rotation(const Vec6& q);
Vec6 HomePose(const BlindGeometry& g);

// Leg i's vector from base joint to platform joint, in {B}.
Vec3 LegVector(const BlindGeometry& g, const Vec6& q, int leg);
Vec6 LegLengths(const BlindGeometry& g, const Vec6& q);

// Angle (rad) by which the upper leg body (hung from the platform's joint)
// is turned about the leg axis against the lower body (on the base's joint),
// each body's frame built from its joint's two explicit angles. Defined up
// to a constant per leg; differences from home are what matter.
Vec6 LegBodyTwist(const BlindGeometry& g, const Vec6& q);

// Forward kinematics along a sampled motion: the pose at which
// `residual(q)` (six values) vanishes, by Newton's method on a
// central-difference Jacobian that is kept from one solve to the next while
// it still shrinks the residual a hundredfold a step (a chord method: one sample
// to the next the pose moves by a fraction of a millimetre and the Jacobian
// barely changes, and one residual costs what a twelfth of a Jacobian does).
// Converges to the same `tolerance` (m) as a fresh Newton solve; throws
// std::runtime_error if it does not within 50 steps.
class PoseSolver {
 public:
  template <typename Residual>
  Vec6 Solve(const Residual& residual, Vec6 guess, double tolerance = 1e-12);

 private:
  template <typename Residual>
  void Factor(const Residual& residual, const Vec6& q);

  Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> jacobian_;
  bool factored_ = false;
};

// One pose from `guess`, with a Jacobian of its own (PoseSolver above).
template <typename Residual>
Vec6 SolvePose(const Residual& residual, Vec6 guess, double tolerance = 1e-12);

}  // namespace edsp::blind

#include "edsp/blindrig/solve_pose.inl"
