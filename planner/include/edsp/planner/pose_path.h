#pragma once
// The geometry of a motion, apart from its timing: the platform's pose as a
// function of a path parameter u, with its first two derivatives (so the
// setpoint's velocity and acceleration follow from u's). A move's u runs
// over [0, 1] along a PivotPath; a program's u is its own time.

#include <cstdint>
#include <memory>
#include <string>

#include "edsp/planner/trajectory.h"
#include "edsp/planner/work_frame.h"

namespace edsp {

// What the setpoints at u are named: a program's segment (its name lives
// as long as the path), else the motion's activity (name null).
struct PathSegment {
  const std::string* name = nullptr;
  std::int32_t index = 0;
  bool dwells = false;  // a program's dwell (Trajectory::dwells)
};

class PosePath {
 public:
  virtual ~PosePath() = default;
  virtual double length() const = 0;  // u runs over [0, length()]
  // pose = P(u), velocity = dP/du, acceleration = d²P/du² (x y z roll pitch yaw).
  virtual PoseSample At(double u) const = 0;
  // P(u) alone (what the path check samples).
  virtual Vector6 PoseAt(double u) const = 0;
  // How far it goes, for the reply ("0.0200 m, 0.0000 rad about the pivot").
  virtual std::string Extent() const = 0;
  virtual PathSegment SegmentAt(double /*u*/) const { return {}; }
  // Whether the legs' acceleration limit is checked along it: a program's
  // steps are its data's (as CheckTrajectory takes them), a move's are planned.
  virtual bool ChecksLegAcceleration() const { return true; }
};

// The pivot on a straight line from `from` to `to` (in `frame`, about
// `pivot_M`) while the platform turns about it along the shortest rotation.
class PivotPath final : public PosePath {
 public:
  PivotPath(const WorkFrame& frame, const Vector3& pivot_M, const FramedPose& from, const FramedPose& to);
  double length() const override { return 1.0; }
  PoseSample At(double u) const override;
  Vector6 PoseAt(double u) const override;
  std::string Extent() const override;
  double distance_m() const { return (to_.t - from_.t).norm(); }
  double angle_rad() const { return angle_rad_; }

 private:
  WorkFrame frame_;
  Vector3 pivot_M_;
  FramedPose from_, to_;
  Vector3 axis_W_ = Vector3::UnitZ();  // of R_from⁻¹ R_to, in from's axes
  double angle_rad_ = 0.0;
};

// A program (named motions, a CSV) played on its own clock: u is its time.
class ProgramPath final : public PosePath {
 public:
  explicit ProgramPath(std::unique_ptr<TrajectorySequence> program) : program_(std::move(program)) {}
  double length() const override { return program_->duration_s(); }
  PoseSample At(double u) const override { return program_->Sample(u); }
  Vector6 PoseAt(double u) const override { return program_->Sample(u).pose; }
  std::string Extent() const override;
  PathSegment SegmentAt(double u) const override;
  bool ChecksLegAcceleration() const override { return false; }
  const TrajectorySequence& program() const { return *program_; }

 private:
  std::unique_ptr<TrajectorySequence> program_;
};

}  // namespace edsp
