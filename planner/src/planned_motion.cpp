#include "edsp/planner/planned_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace edsp {

namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();
// A stop ramps its deceleration in over this long: the legs' acceleration
// is their limit, and no velocity or acceleration steps.
constexpr double kStopRamp_s = 0.004;

// The tightest of limit/extent over the pivot's and the rotation's.
double PathRate(double per_m, double distance_m, double per_rad, double angle_rad) {
  double rate = kUnbounded;
  if (distance_m > 0.0) rate = std::min(rate, per_m / distance_m);
  if (angle_rad > 0.0) rate = std::min(rate, per_rad / angle_rad);
  return rate;
}

// max over the path of the fastest leg's |dL/du|: how much leg motion one
// unit of u costs, for the stop's deceleration.
double LegSensitivity(const PlatformModel& model, const PosePath& path) {
  constexpr int kSamples = 200;
  const double length = path.length();
  const double h = std::max(length * 1e-5, 1e-9);
  double worst = 0.0;
  for (int k = 0; k <= kSamples; ++k) {
    const double u = std::clamp(length * k / kSamples, h, std::max(h, length - h));
    const Vector6 ahead = model.LegLengths(Pose::FromVector(path.At(u + h).pose));
    const Vector6 behind = model.LegLengths(Pose::FromVector(path.At(u - h).pose));
    worst = std::max(worst, (ahead - behind).cwiseAbs().maxCoeff() / (2.0 * h));
  }
  return worst;
}

ScalarLimits StopLimits(const PlatformModel& model, const PosePath& path, const ScalarLimits& halt) {
  const double sensitivity = LegSensitivity(model, path);
  const double accel = sensitivity > 0.0 ? model.config().motion.leg_accel_max_m_s2 / sensitivity : halt.acceleration;
  const double stop_accel = std::max(accel, halt.acceleration);
  return {halt.velocity, stop_accel, std::max(halt.jerk, stop_accel / kStopRamp_s)};
}

PathCheck CheckMotion(const PlatformModel& model, const PlannedMotion& m, double rate_hz) {
  PathLimits limits = PathLimitsOf(model);
  if (!m.path->ChecksLegAcceleration()) limits.leg_accel_max_m_s2 = 0.0;
  return CheckPath(
      model, limits, [&](double t) { return m.path->PoseAt(MotionState(m, t).position); }, m.duration_s(), rate_hz);
}

}  // namespace

MoveLimits ConfigMoveLimits(const PlatformModel& model) {
  const MotionLimits& m = model.config().motion;
  return {m.speed_max_m_s, m.speed_max_rad_s, m.accel_max_m_s2, m.accel_max_rad_s2, m.jerk_max_m_s3, m.jerk_max_rad_s3};
}

PlannedMotion PlanMove(const PlatformModel& model, const WorkFrame& frame, const Vector3& pivot_M,
                       const Transform& from, const FramedPose& to, const MoveLimits& l, double check_rate_hz) {
  auto path = std::make_shared<PivotPath>(frame, pivot_M, InFrame(frame, pivot_M, from), to);
  const double d = path->distance_m(), angle = path->angle_rad();
  PlannedMotion m;
  m.activity = "move";
  m.frame = frame.name;
  m.path = path;
  if (d > 0.0 || angle > 0.0) {
    const ScalarLimits u{PathRate(l.speed_m_s, d, l.speed_rad_s, angle),
                         PathRate(l.accel_m_s2, d, l.accel_rad_s2, angle),
                         PathRate(l.jerk_m_s3, d, l.jerk_rad_s3, angle)};
    m.timing = JerkProfile::RestToRest(1.0, u);
    m.halt = u;
    if (!(m.duration_s() <= kLongestMove_s)) {
      m.check.limit = PathLimit::kDuration;
      m.check.value = m.duration_s();
      m.check.bound = kLongestMove_s;
      return m;
    }
    m.stop = StopLimits(model, *path, u);
  }
  m.check = CheckMotion(model, m, check_rate_hz);
  return m;
}

PlannedMotion PlanProgram(const PlatformModel& model, std::unique_ptr<TrajectorySequence> program, const MoveLimits& l,
                          double check_rate_hz) {
  auto path = std::make_shared<ProgramPath>(std::move(program));
  // The program's own peak speeds bound how fast its clock may be slowed:
  // the slowing adds at most the move limits' acceleration to its own.
  double peak_m_s = 0.0, peak_rad_s = 0.0;
  for (double t = 0.0; t <= path->length(); t += 0.01) {
    const Vector6 v = path->At(t).velocity;
    peak_m_s = std::max(peak_m_s, v.head<3>().norm());
    peak_rad_s = std::max(peak_rad_s, v.tail<3>().norm());
  }
  PlannedMotion m;
  m.path = path;
  m.timing = JerkProfile::Clock(path->length());
  const double a = std::min(PathRate(l.accel_m_s2, peak_m_s, l.accel_rad_s2, peak_rad_s), 1e3);
  const double j = std::min(PathRate(l.jerk_m_s3, peak_m_s, l.jerk_rad_s3, peak_rad_s), 1e6);
  m.halt = {1.0, a, j};
  m.stop = StopLimits(model, *path, m.halt);
  m.check = CheckMotion(model, m, check_rate_hz);
  return m;
}

ScalarState MotionState(const PlannedMotion& m, double t_s) { return m.timing.At(t_s); }

PoseSample SampleMotion(const PlannedMotion& m, double t_s) {
  const ScalarState u = MotionState(m, t_s);
  const PoseSample p = m.path->At(std::clamp(u.position, 0.0, m.path->length()));
  PoseSample s;
  s.pose = p.pose;
  s.velocity = p.velocity * u.velocity;
  s.acceleration = p.acceleration * u.velocity * u.velocity + p.velocity * u.acceleration;
  return s;
}

}  // namespace edsp
