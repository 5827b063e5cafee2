#include "edsp/sim/paper_table.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {

std::vector<TestMotion> PaperTestMotions() {
  constexpr double kThirtyDeg = 30.0 * 3.14159265358979323846 / 180.0;
  return {{"Lz", 2, 0.5}, {"Lx", 0, 0.5}, {"Rz", 5, kThirtyDeg}, {"Ry", 4, kThirtyDeg}};
}

std::vector<Pose> MotionPoses(const TestMotion& motion, const Pose& home, int count) {
  std::vector<Pose> poses;
  poses.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    Vector6 q = home.ToVector();
    q(motion.axis) += motion.amplitude * (-1.0 + 2.0 * k / (count - 1));
    poses.push_back(Pose::FromVector(q));
  }
  return poses;
}

double PointAError(const PlatformModel& model, const Pose& target, PrMode mode) {
  // A perfect servo: the encoders read exactly what was commanded; the screws
  // then add their true signed PR, which forward kinematics accounts for. It
  // starts from home, not from the target (which would already be a root).
  const Vector6 commanded = model.CompensatedLengths(target, mode);
  const FkResult fk = SolveForward(model, commanded, model.home_pose());
  if (!fk.ok()) {
    throw std::runtime_error(fmt::format("forward kinematics failed at {} ({}, residual {} m)", DescribePose(target),
                                         FkStatusName(fk.status), fk.residual_m));
  }
  return (model.ObservationPoint(fk.pose) - model.ObservationPoint(target)).norm();
}

std::vector<MotionRow> PaperTable(const PlatformModel& model, int poses_per_motion) {
  std::vector<MotionRow> rows;
  for (const TestMotion& motion : PaperTestMotions()) {
    MotionRow row{motion, {}};
    for (const Pose& pose : MotionPoses(motion, model.home_pose(), poses_per_motion)) {
      const WorkspaceCheck check = CheckWorkspace(model, pose);
      if (!check.ok()) {
        throw std::runtime_error(fmt::format("motion {}: pose {} is outside the workspace: {}", motion.name,
                                             DescribePose(pose), check.Describe()));
      }
      for (std::size_t m = 0; m < kTableModes.size(); ++m) {
        row.max_error_m[m] = std::max(row.max_error_m[m], PointAError(model, pose, kTableModes[m]));
      }
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace edsp
