#include "edsp/planner/pose_path.h"

#include <algorithm>

#include <fmt/format.h>

namespace edsp {

PivotPath::PivotPath(const WorkFrame& frame, const Vector3& pivot_M, const FramedPose& from, const FramedPose& to)
    : frame_(frame), pivot_M_(pivot_M), from_(from), to_(to) {
  const Eigen::AngleAxisd turn(Matrix3(from.R.transpose() * to.R));
  angle_rad_ = std::abs(turn.angle());
  if (angle_rad_ > 0.0) axis_W_ = turn.axis() * (turn.angle() < 0.0 ? -1.0 : 1.0);
}

Vector6 PivotPath::PoseAt(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  FramedPose p;
  p.t = from_.t + u * (to_.t - from_.t);
  p.R = from_.R * Eigen::AngleAxisd(u * angle_rad_, axis_W_).toRotationMatrix();
  if (u >= 1.0) p = to_;  // exactly where asked
  return PoseOf(PlatformPose(frame_, pivot_M_, p)).ToVector();
}

PoseSample PivotPath::At(double u) const {
  // Derivatives by central differences: the path is smooth in u, and the
  // roll-pitch-yaw rates it yields are what EDSP_SETPOINT carries.
  constexpr double h = 1e-4;
  PoseSample s;
  s.pose = PoseAt(u);
  const Vector6 ahead = PoseAt(u + h), behind = PoseAt(u - h);
  const double span = std::min(u + h, 1.0) - std::max(u - h, 0.0);
  s.velocity = (ahead - behind) / span;
  if (u - h >= 0.0 && u + h <= 1.0) s.acceleration = (ahead - 2.0 * s.pose + behind) / (h * h);
  return s;
}

std::string PivotPath::Extent() const {
  return fmt::format("{:.4f} m, {:.4f} rad about the pivot", distance_m(), angle_rad());
}

std::string ProgramPath::Extent() const { return fmt::format("{:.3f} s of its own clock", length()); }

PathSegment ProgramPath::SegmentAt(double u) const {
  const int index = program_->SegmentAt(u);
  return {&program_->SegmentName(index), static_cast<std::int32_t>(index), program_->SegmentDwells(index)};
}

}  // namespace edsp
