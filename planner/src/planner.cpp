#include "edsp/planner/planner.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/kinematics/workspace.h"

namespace edsp {

void CheckTrajectory(const PlatformModel& model, const TrajectorySequence& sequence,
                     double rate_hz) {
  const double duration = sequence.duration_s();
  const auto samples = static_cast<long>(std::ceil(duration * rate_hz));
  const double speed_max = model.config().limits.leg_speed_max_m_s;
  Vector6 previous_length = Vector6::Zero();
  double previous_t = 0.0;
  for (long k = 0; k <= samples; ++k) {
    const double t = std::min(duration, static_cast<double>(k) / rate_hz);
    const PoseSample sample = sequence.Sample(t);
    const Pose pose = Pose::FromVector(sample.pose);
    const WorkspaceCheck check = CheckWorkspace(model, pose);
    if (!check.ok()) {
      throw std::invalid_argument(fmt::format(
          "trajectory segment \"{}\" at t = {:.3f} s leaves the workspace: {}",
          sequence.SegmentName(sequence.SegmentAt(t)), t, check.Describe()));
    }
    // Leg speed as the bridge will see it: the step between two setpoints.
    const Vector6 length = model.Solve(pose).length_m;
    if (k > 0 && t > previous_t) {
      Vector6::Index leg = 0;
      const double speed = ((length - previous_length).cwiseAbs() / (t - previous_t)).maxCoeff(&leg);
      if (speed > speed_max) {
        throw std::invalid_argument(fmt::format(
            "trajectory segment \"{}\" at t = {:.3f} s moves leg {} at {:.3f} m/s, above [limits] "
            "leg_speed_max_m_s = {} (slow the motion down)",
            sequence.SegmentName(sequence.SegmentAt(t)), t, leg + 1, speed, speed_max));
      }
    }
    previous_length = length;
    previous_t = t;
  }
}

Planner::Planner(const PlatformModel& model, std::unique_ptr<TrajectorySequence> sequence,
                 std::int64_t session_id)
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
  return msg;
}

bool Planner::Finished(std::int64_t now_utime) const {
  return static_cast<double>(now_utime - start_utime_) * 1e-6 >= sequence_->duration_s();
}

}  // namespace edsp
