#include "edsp/kinematics/path_check.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace edsp {

PathLimits PathLimitsOf(const PlatformModel& model) {
  return {model.config().limits.leg_speed_max_m_s, model.config().motion.leg_accel_max_m_s2};
}

std::string PathCheck::Describe() const {
  switch (limit) {
    case PathLimit::kNone:
      return fmt::format("within every limit (peak leg speed {:.4f} m/s, acceleration {:.3f} m/s^2)",
                         peak_leg_speed_m_s, peak_leg_accel_m_s2);
    case PathLimit::kWorkspace: return fmt::format("at t = {:.3f} s: {}", t_s, workspace.Describe());
    case PathLimit::kLegSpeed:
      return fmt::format("at t = {:.3f} s: leg {} at {:.4f} m/s, {:.4f} m/s above [limits] leg_speed_max_m_s = {}", t_s,
                         leg + 1, value, value - bound, bound);
    case PathLimit::kDuration:
      return fmt::format("the path would last {:.6g} s, beyond the {} s allowed (ask for more speed)", value, bound);
    case PathLimit::kLegAcceleration:
      return fmt::format(
          "at t = {:.3f} s: leg {} accelerates at {:.3f} m/s^2, {:.3f} m/s^2 above [motion] leg_accel_max_m_s2 = {}",
          t_s, leg + 1, value, value - bound, bound);
  }
  return "unknown limit";
}

namespace {

constexpr double kConditioningStep_m = 0.002;

// The largest |v(i)| and its leg.
double Largest(const Vector6& v, int* leg) {
  Vector6::Index i = 0;
  const double largest = v.cwiseAbs().maxCoeff(&i);
  *leg = static_cast<int>(i);
  return largest;
}

}  // namespace

PathCheck CheckPath(const PlatformModel& model, const PathLimits& limits, const PathPoseAt& pose_at, double duration_s,
                    double rate_hz) {
  PathCheck result;
  // A day of samples at most: beyond, a unit typo (or a NaN) and no path.
  constexpr double kLongest_s = 86400.0;
  if (!(duration_s >= 0.0 && duration_s <= kLongest_s)) {
    result.limit = PathLimit::kDuration;
    result.value = duration_s;
    result.bound = kLongest_s;
    return result;
  }
  const long samples = static_cast<long>(std::ceil(std::max(0.0, duration_s) * rate_hz - 1e-9));
  Vector6 length_before = Vector6::Zero(), speed_before = Vector6::Zero(), length_conditioned = Vector6::Zero();
  double t_before = 0.0, dt_before = 0.0;
  for (long k = 0; k <= samples; ++k) {
    const double t = std::min(duration_s, static_cast<double>(k) / rate_hz);
    const Pose pose = Pose::FromVector(pose_at(t));
    const LegSolution legs = model.Solve(pose);
    const Vector6& length = legs.length_m;
    // The conditioning (an SVD, ten times the rest of a sample) varies
    // slowly with the pose: checked again once a leg has moved
    // kConditioningStep_m, and at both ends.
    const bool condition_due =
        k == 0 || k == samples || (length - length_conditioned).cwiseAbs().maxCoeff() >= kConditioningStep_m;
    result.workspace =
        !pose.IsFinite() ? WorkspaceCheck{WorkspaceLimit::kNonFinite, -1, 0.0, 0.0} : CheckLegs(model, legs);
    if (result.workspace.ok() && condition_due) {
      result.workspace = CheckConditioning(model, pose);
      length_conditioned = length;
    }
    if (!result.workspace.ok()) {
      result.limit = PathLimit::kWorkspace;
      result.t_s = t;
      return result;
    }
    if (k > 0 && t > t_before) {
      const double dt = t - t_before;
      const Vector6 speed = (length - length_before) / dt;
      int leg = 0;
      const double fastest = Largest(speed, &leg);
      result.peak_leg_speed_m_s = std::max(result.peak_leg_speed_m_s, fastest);
      if (fastest > limits.leg_speed_max_m_s) {
        return PathCheck{
            PathLimit::kLegSpeed,      t, {}, leg, fastest, limits.leg_speed_max_m_s, result.peak_leg_speed_m_s,
            result.peak_leg_accel_m_s2};
      }
      if (k > 1 && limits.leg_accel_max_m_s2 > 0.0) {
        const double accel = Largest((speed - speed_before) / (0.5 * (dt + dt_before)), &leg);
        result.peak_leg_accel_m_s2 = std::max(result.peak_leg_accel_m_s2, accel);
        if (accel > limits.leg_accel_max_m_s2) {
          return PathCheck{
              PathLimit::kLegAcceleration, t, {}, leg, accel, limits.leg_accel_max_m_s2, result.peak_leg_speed_m_s,
              result.peak_leg_accel_m_s2};
        }
      }
      speed_before = speed;
      dt_before = dt;
    }
    length_before = length;
    t_before = t;
  }
  return result;
}

}  // namespace edsp
