#pragma once
// A whole path checked before its first setpoint, at the planner's cycle:
// every pose inside the workspace (the parts of CheckWorkspace, the very
// check the kinematics node applies to each setpoint at run time: strokes
// and joint angles at every sample, the slowly varying conditioning each
// time a leg has moved 2 mm and at both ends), and every leg
// within the drives' speed and acceleration as the bridge will see them
// (differences of the leg lengths between successive setpoints). A refusal
// names the first violation: when along the path, which limit, which leg,
// by how much.

#include <functional>
#include <string>

#include "edsp/kinematics/platform_model.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {

enum class PathLimit { kNone, kWorkspace, kLegSpeed, kLegAcceleration, kDuration };

struct PathLimits {
  double leg_speed_max_m_s = 0.0;
  double leg_accel_max_m_s2 = 0.0;  // ≤ 0: not checked (a CSV's piecewise-linear poses)
};

// [limits] leg_speed_max_m_s and [motion] leg_accel_max_m_s2 of the model's config.
PathLimits PathLimitsOf(const PlatformModel& model);

struct PathCheck {
  PathLimit limit = PathLimit::kNone;
  double t_s = 0.0;          // time along the path of the first violation
  WorkspaceCheck workspace;  // kWorkspace: which workspace limit
  int leg = -1;              // kLegSpeed, kLegAcceleration: 0-based
  double value = 0.0, bound = 0.0;
  double peak_leg_speed_m_s = 0.0;  // over the path checked (up to a violation)
  double peak_leg_accel_m_s2 = 0.0;
  bool ok() const { return limit == PathLimit::kNone; }
  // "at t = 1.234 s: leg 3 at 0.61 m/s, 0.11 m/s above [limits] leg_speed_max_m_s = 0.5"
  std::string Describe() const;
};

// The pose ({M} in {B}, x y z roll pitch yaw) at time t along the path.
using PathPoseAt = std::function<Vector6(double t_s)>;

// Samples [0, duration_s] at `rate_hz` (and its end) and returns the first
// violation, or ok with the peaks.
PathCheck CheckPath(const PlatformModel& model, const PathLimits& limits, const PathPoseAt& pose_at, double duration_s,
                    double rate_hz = 1000.0);

}  // namespace edsp
