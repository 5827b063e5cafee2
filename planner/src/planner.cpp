#include "edsp/planner/planner.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/kinematics/path_check.h"

namespace edsp {

void CheckTrajectory(const PlatformModel& model, const TrajectorySequence& sequence, double rate_hz) {
  PathLimits limits = PathLimitsOf(model);
  limits.leg_accel_max_m_s2 = 0.0;  // a CSV's poses are piecewise linear: its steps are the data's
  const PathCheck check = CheckPath(
      model, limits, [&](double t) { return sequence.Sample(t).pose; }, sequence.duration_s(), rate_hz);
  if (!check.ok()) throw std::invalid_argument(TrajectoryViolation(sequence, check));
}

std::string TrajectoryViolation(const TrajectorySequence& sequence, const PathCheck& check) {
  const std::string segment = sequence.SegmentName(sequence.SegmentAt(check.t_s));
  if (check.limit == PathLimit::kWorkspace) {
    return fmt::format("trajectory segment \"{}\" at t = {:.3f} s leaves the workspace: {}", segment, check.t_s,
                       check.workspace.Describe());
  }
  return fmt::format("trajectory segment \"{}\" {} (slow the motion down)", segment, check.Describe());
}

Planner::Planner(const PlatformModel& model, std::unique_ptr<TrajectorySequence> sequence, std::int64_t session_id)
    : sequence_(std::move(sequence)), session_id_(session_id) {
  if (sequence_ == nullptr || sequence_->size() == 0) {
    throw std::invalid_argument("planner: empty trajectory");
  }
  CheckTrajectory(model, *sequence_);
}

pose_setpoint_t Planner::Step(std::int64_t now_utime) {
  const double t = static_cast<double>(now_utime - start_utime_) * 1e-6;
  const PoseSample sample = sequence_->Sample(t);
  const int segment = sequence_->SegmentAt(t);
  pose_setpoint_t msg{};
  msg.utime = now_utime;
  msg.seq = ++seq_;
  msg.session_id = session_id_;
  for (int k = 0; k < 6; ++k) {
    msg.pose[k] = sample.pose(k);
    msg.velocity[k] = sample.velocity(k);
    msg.acceleration[k] = sample.acceleration(k);
  }
  msg.trajectory = sequence_->SegmentName(segment);
  msg.segment = segment;
  msg.phase = sequence_->SegmentDwells(segment) ? pose_setpoint_t::PHASE_DWELL : pose_setpoint_t::PHASE_MOVE;
  return msg;
}

bool Planner::Finished(std::int64_t now_utime) const {
  return static_cast<double>(now_utime - start_utime_) * 1e-6 >= sequence_->duration_s();
}

}  // namespace edsp
