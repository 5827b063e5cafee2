#pragma once
// The planner's logic, free of any bus: it owns a trajectory sequence that was
// checked against the workspace before the first setpoint, and turns an
// absolute clock into setpoints (so missed cycles never make it drift). After
// the last segment it holds the final pose.

#include <cstdint>
#include <memory>
#include <string>

#include "edsp/kinematics/path_check.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/planner/trajectory.h"

namespace edsp {

// Samples the whole trajectory at `rate_hz`; throws std::invalid_argument
// naming the segment, the time and the limit of the first pose outside.
void CheckTrajectory(const PlatformModel& model, const TrajectorySequence& sequence, double rate_hz = 1000.0);

// "trajectory segment \"Lx/move\" at t = … s leaves the workspace: …": the
// first violation `check` found along `sequence`, for the operator.
std::string TrajectoryViolation(const TrajectorySequence& sequence, const PathCheck& check);

class Planner {
 public:
  // Throws std::invalid_argument if any pose of the sequence is unreachable.
  Planner(const PlatformModel& model, std::unique_ptr<TrajectorySequence> sequence, std::int64_t session_id);

  void Start(std::int64_t start_utime) { start_utime_ = start_utime; }
  // The setpoint for time `now_utime` (microseconds, same clock as Start).
  pose_setpoint_t Step(std::int64_t now_utime);
  bool Finished(std::int64_t now_utime) const;
  const TrajectorySequence& sequence() const { return *sequence_; }

 private:
  std::unique_ptr<TrajectorySequence> sequence_;
  std::int64_t session_id_;
  std::int64_t start_utime_ = 0;
  std::int64_t seq_ = 0;
};

}  // namespace edsp
