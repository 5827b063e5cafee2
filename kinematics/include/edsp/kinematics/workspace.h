#pragma once
// Workspace checks: a pose is reachable only if every leg is within its
// stroke, every leg axis is within the Hooke's joints' angle limit from both
// platforms' normals, and the platform is far from a singularity.

#include <string>

#include "edsp/kinematics/platform_model.h"

namespace edsp {

enum class WorkspaceLimit {
  kNone,       // inside
  kNonFinite,  // NaN or infinite pose component
  kLegTooShort,
  kLegTooLong,
  kBaseJointAngle,
  kPlatformJointAngle,
  kConditioning,
};

struct WorkspaceCheck {
  WorkspaceLimit limit = WorkspaceLimit::kNone;
  int leg = -1;        // 0-based leg index where a per-leg limit bit, else -1
  double value = 0.0;  // the offending value (m, rad or condition number)
  double bound = 0.0;  // the limit it crossed
  bool ok() const { return limit == WorkspaceLimit::kNone; }
  std::string Describe() const;  // "leg 3 length 2.61 m exceeds leg_max_m 2.45 m"
};

// Condition number σmax/σmin of the geometric Jacobian with its rotation
// columns divided by the platform's joint radius, so metres meet metres.
double JacobianCondition(const PlatformModel& model, const Pose& X_BM);

// Every limit, in the order above: what the kinematics node applies to each setpoint.
WorkspaceCheck CheckWorkspace(const PlatformModel& model, const Pose& X_BM);

// Its parts, for a caller that has the legs solved already or samples the
// slowly varying conditioning less often (path_check.h):
// strokes and joint angles of a solved pose,
WorkspaceCheck CheckLegs(const PlatformModel& model, const LegSolution& legs);
// and the distance from a singularity.
WorkspaceCheck CheckConditioning(const PlatformModel& model, const Pose& X_BM);

// Joint-angle check alone (cheap; used on forward-kinematics results).
WorkspaceCheck CheckJointAngles(const PlatformModel& model, const LegSolution& legs);

}  // namespace edsp
