#include "edsp/kinematics/workspace.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

namespace edsp {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

double AngleBetween(const Vector3& a, const Vector3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// The characteristic length that makes the Jacobian's rotation columns
// comparable with its translation columns: the platform joints' mean radius.
double JointRadius(const PlatformGeometry& g) { return g.p_MoPi_M.colwise().norm().mean(); }

}  // namespace

std::string WorkspaceCheck::Describe() const {
  switch (limit) {
    case WorkspaceLimit::kNone: return "inside the workspace";
    case WorkspaceLimit::kNonFinite: return "pose has a non-finite component";
    case WorkspaceLimit::kLegTooShort:
      return fmt::format("leg {} length {:.6f} m is below leg_min_m {:.6f} m", leg + 1, value, bound);
    case WorkspaceLimit::kLegTooLong:
      return fmt::format("leg {} length {:.6f} m exceeds leg_max_m {:.6f} m", leg + 1, value, bound);
    case WorkspaceLimit::kBaseJointAngle:
      return fmt::format("leg {} is {:.3f} deg from the base normal, beyond joint_angle_max_rad ({:.3f} deg)", leg + 1,
                         value * kRadToDeg, bound * kRadToDeg);
    case WorkspaceLimit::kPlatformJointAngle:
      return fmt::format("leg {} is {:.3f} deg from the platform normal, beyond joint_angle_max_rad ({:.3f} deg)",
                         leg + 1, value * kRadToDeg, bound * kRadToDeg);
    case WorkspaceLimit::kConditioning:
      return fmt::format(
          "Jacobian condition number {:.1f} exceeds jacobian_condition_max {:.1f} (near a "
          "singularity)",
          value, bound);
  }
  return "unknown limit";
}

double JacobianCondition(const PlatformModel& model, const Pose& X_BM) {
  Matrix6 J = model.TwistJacobian(X_BM);
  J.rightCols<3>() /= JointRadius(model.config().geometry);
  // σ² are the eigenvalues of JᵀJ: a symmetric eigensolver is several times
  // cheaper than an SVD, and squaring costs nothing that matters below the
  // limits a platform runs at (conditions of 10² square to 10⁴).
  const Eigen::SelfAdjointEigenSolver<Matrix6> eigen(J.transpose() * J, Eigen::EigenvaluesOnly);
  const Vector6& squared = eigen.eigenvalues();  // ascending
  return squared(0) > 0.0 ? std::sqrt(squared(5) / squared(0)) : std::numeric_limits<double>::infinity();
}

WorkspaceCheck CheckJointAngles(const PlatformModel& model, const LegSolution& legs) {
  const double limit = model.config().limits.joint_angle_max_rad;
  // Cosines first (u is a unit vector): the angle's trigonometry only for a leg past the limit.
  const double cos_limit = std::cos(limit);
  const Vector3 platform_normal = legs.R_BM.col(2);
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = legs.u_B.col(i);
    if (!(u.z() >= cos_limit)) {
      const double base_angle = AngleBetween(u, Vector3::UnitZ());
      if (!(base_angle <= limit)) return {WorkspaceLimit::kBaseJointAngle, i, base_angle, limit};
    }
    if (!(u.dot(platform_normal) >= cos_limit)) {
      const double platform_angle = AngleBetween(u, platform_normal);
      if (!(platform_angle <= limit)) return {WorkspaceLimit::kPlatformJointAngle, i, platform_angle, limit};
    }
  }
  return {};
}

WorkspaceCheck CheckLegs(const PlatformModel& model, const LegSolution& legs) {
  const WorkspaceLimits& limits = model.config().limits;
  for (int i = 0; i < kNumLegs; ++i) {
    const double length = legs.length_m(i);
    if (!(length >= limits.leg_min_m)) {
      return {WorkspaceLimit::kLegTooShort, i, length, limits.leg_min_m};
    }
    if (!(length <= limits.leg_max_m)) {
      return {WorkspaceLimit::kLegTooLong, i, length, limits.leg_max_m};
    }
  }
  return CheckJointAngles(model, legs);
}

WorkspaceCheck CheckConditioning(const PlatformModel& model, const Pose& X_BM) {
  const double bound = model.config().limits.jacobian_condition_max;
  const double condition = JacobianCondition(model, X_BM);
  if (!(condition <= bound)) return {WorkspaceLimit::kConditioning, -1, condition, bound};
  return {};
}

WorkspaceCheck CheckWorkspace(const PlatformModel& model, const Pose& X_BM) {
  if (!X_BM.IsFinite()) return {WorkspaceLimit::kNonFinite, -1, 0.0, 0.0};
  const WorkspaceCheck legs = CheckLegs(model, model.Solve(X_BM));
  if (!legs.ok()) return legs;
  return CheckConditioning(model, X_BM);
}

}  // namespace edsp
