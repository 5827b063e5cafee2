#include "edsp/kinematics/workspace.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>
#include <fmt/format.h>

namespace edsp {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

double AngleBetween(const Vector3& a, const Vector3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// The characteristic length that makes the Jacobian's rotation columns
// comparable with its translation columns: the platform joints' mean radius.
double JointRadius(const PlatformGeometry& g) {
  return g.p_MoPi_M.colwise().norm().mean();
}

}  // namespace

std::string WorkspaceCheck::Describe() const {
  switch (limit) {
    case WorkspaceLimit::kNone: return "inside the workspace";
    case WorkspaceLimit::kNonFinite: return "pose has a non-finite component";
    case WorkspaceLimit::kLegTooShort:
      return fmt::format("leg {} length {:.6f} m is below leg_min_m {:.6f} m", leg + 1, value,
                         bound);
    case WorkspaceLimit::kLegTooLong:
      return fmt::format("leg {} length {:.6f} m exceeds leg_max_m {:.6f} m", leg + 1, value,
                         bound);
    case WorkspaceLimit::kBaseJointAngle:
      return fmt::format(
          "leg {} is {:.3f} deg from the base normal, beyond joint_angle_max_rad ({:.3f} deg)",
          leg + 1, value * kRadToDeg, bound * kRadToDeg);
    case WorkspaceLimit::kPlatformJointAngle:
      return fmt::format(
          "leg {} is {:.3f} deg from the platform normal, beyond joint_angle_max_rad ({:.3f} deg)",
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
  const Eigen::JacobiSVD<Matrix6> svd(J);
  const Vector6& sv = svd.singularValues();
  return sv(5) > 0.0 ? sv(0) / sv(5) : std::numeric_limits<double>::infinity();
}

WorkspaceCheck CheckJointAngles(const PlatformModel& model, const LegSolution& legs) {
  WorkspaceCheck check;
  const double limit = model.config().limits.joint_angle_max_rad;
  const Vector3 platform_normal = legs.R_BM.col(2);
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = legs.u_B.col(i);
    const double base_angle = AngleBetween(u, Vector3::UnitZ());
    const double platform_angle = AngleBetween(u, platform_normal);
    if (!(base_angle <= limit)) return {WorkspaceLimit::kBaseJointAngle, i, base_angle, limit};
    if (!(platform_angle <= limit)) {
      return {WorkspaceLimit::kPlatformJointAngle, i, platform_angle, limit};
    }
  }
  return check;
}

WorkspaceCheck CheckWorkspace(const PlatformModel& model, const Pose& X_BM) {
  if (!X_BM.IsFinite()) return {WorkspaceLimit::kNonFinite, -1, 0.0, 0.0};
  const WorkspaceLimits& limits = model.config().limits;
  const LegSolution legs = model.Solve(X_BM);
  for (int i = 0; i < kNumLegs; ++i) {
    const double length = legs.length_m(i);
    if (!(length >= limits.leg_min_m)) {
      return {WorkspaceLimit::kLegTooShort, i, length, limits.leg_min_m};
    }
    if (!(length <= limits.leg_max_m)) {
      return {WorkspaceLimit::kLegTooLong, i, length, limits.leg_max_m};
    }
  }
  const WorkspaceCheck angles = CheckJointAngles(model, legs);
  if (!angles.ok()) return angles;
  const double condition = JacobianCondition(model, X_BM);
  if (!(condition <= limits.jacobian_condition_max)) {
    return {WorkspaceLimit::kConditioning, -1, condition, limits.jacobian_condition_max};
  }
  return {};
}

}  // namespace edsp
