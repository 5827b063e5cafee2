#pragma once
// One motion the motion service plays: where it goes (a PosePath), when (a
// JerkProfile of its path parameter, so every axis arrives together), how
// it may be halted and stopped, and its whole path checked before its first
// setpoint (path_check.h).

#include <cstdint>
#include <memory>
#include <string>

#include "edsp/kinematics/path_check.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/jerk_profile.h"
#include "edsp/planner/pose_path.h"

namespace edsp {

// Cartesian limits of one motion: the pivot's and the rotation's.
struct MoveLimits {
  double speed_m_s = 0.0, speed_rad_s = 0.0;
  double accel_m_s2 = 0.0, accel_rad_s2 = 0.0;
  double jerk_m_s3 = 0.0, jerk_rad_s3 = 0.0;
};

// The longest a move may last: beyond, its speed was a typo, and its check
// alone would hold the planner's worker for seconds.
inline constexpr double kLongestMove_s = 600.0;

// [motion]'s limits, the most any move may ask for.
MoveLimits ConfigMoveLimits(const PlatformModel& model);

struct PlannedMotion {
  std::int64_t request_id = 0;
  std::string activity;  // "move", "approach", "run Lz,Lx", ...
  std::string frame = "base";
  std::shared_ptr<const PosePath> path;
  JerkProfile timing;  // of u along path
  ScalarLimits halt;   // u-space acceleration and jerk a halt keeps within
  ScalarLimits stop;   // u-space: the shortest stop the legs' acceleration allows
  PathCheck check;

  double duration_s() const { return timing.duration_s(); }
  Vector6 end_pose() const { return path->At(timing.end().position).pose; }
};

// From X_BM `from` to the pose `to` in `frame` about `pivot_M`: the pivot
// on a straight line, turning about it, jerk-limited within `limits`.
// `check` says whether its whole path is within the platform's limits (a
// move longer than kLongestMove_s is refused unchecked, as kDuration).
PlannedMotion PlanMove(const PlatformModel& model, const WorkFrame& frame, const Vector3& pivot_M,
                       const Transform& from, const FramedPose& to, const MoveLimits& limits, double check_rate_hz);

// A program on its own clock; halts slow that clock within `limits`.
PlannedMotion PlanProgram(const PlatformModel& model, std::unique_ptr<TrajectorySequence> program,
                          const MoveLimits& limits, double check_rate_hz);

// The setpoint's pose, velocity and acceleration `t_s` after the motion's start.
PoseSample SampleMotion(const PlannedMotion& motion, double t_s);
// Where `motion` is along its path `t_s` after its start.
ScalarState MotionState(const PlannedMotion& motion, double t_s);

}  // namespace edsp
