#include "edsp/cueing/classical_washout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {
namespace {

void RequirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("washout {} = {}: must be finite and > 0", name, value));
  }
}

TransferFunction TranslationFilter(double scale, double wn, double zeta, double wb) {
  // k s / ((s² + 2ζωn s + ωn²)(s + ωb))
  return Series({{scale, 0.0}, {1.0, 2.0 * zeta * wn, wn * wn}}, {{1.0}, {1.0, wb}});
}

TransferFunction TiltLowPass(double w, double zeta) { return {{w * w}, {1.0, 2.0 * zeta * w, w * w}}; }

TransferFunction RotationFilter(double scale, double w, double zeta) {
  return {{scale, 0.0}, {1.0, 2.0 * zeta * w, w * w}};
}

}  // namespace

void ValidateWashout(const ClassicalWashoutParameters& p) {
  for (auto [value, name] : {std::pair{p.specific_force_scale, "specific_force_scale"},
                             std::pair{p.angular_velocity_scale, "angular_velocity_scale"}}) {
    if (!(value > 0.0 && value <= 1.0)) {
      throw std::invalid_argument(fmt::format("washout {} = {}: must be in (0, 1]", name, value));
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    RequirePositive(p.translation_break_rad_s(axis), "translation_break_rad_s");
    RequirePositive(p.translation_washout_rad_s(axis), "translation_washout_rad_s");
    RequirePositive(p.rotation_break_rad_s(axis), "rotation_break_rad_s");
  }
  RequirePositive(p.translation_damping, "translation_damping");
  RequirePositive(p.tilt_break_rad_s, "tilt_break_rad_s");
  RequirePositive(p.tilt_damping, "tilt_damping");
  RequirePositive(p.tilt_rate_max_rad_s, "tilt_rate_max_rad_s");
  RequirePositive(p.tilt_accel_max_rad_s2, "tilt_accel_max_rad_s2");
  RequirePositive(p.rotation_damping, "rotation_damping");
  if (!(p.tilt_max_rad > 0.0 && p.tilt_max_rad < 0.5 * kPi)) {
    throw std::invalid_argument(fmt::format("washout tilt_max_rad = {}: must be in (0, π/2)", p.tilt_max_rad));
  }
}

ClassicalWashout::ClassicalWashout(const ClassicalWashoutParameters& parameters, double period_s)
    : parameters_(parameters), period_s_(period_s) {
  ValidateWashout(parameters_);
  const auto& p = parameters_;
  for (int axis = 0; axis < 3; ++axis) {
    translation_[static_cast<std::size_t>(axis)].emplace(
        TranslationFilter(p.specific_force_scale, p.translation_break_rad_s(axis), p.translation_damping,
                          p.translation_washout_rad_s(axis)),
        period_s);
    rotation_[static_cast<std::size_t>(axis)].emplace(
        RotationFilter(p.angular_velocity_scale, p.rotation_break_rad_s(axis), p.rotation_damping), period_s);
  }
  for (auto& tilt : tilt_) tilt.emplace(TiltLowPass(p.tilt_break_rad_s, p.tilt_damping), period_s);
}

double ClassicalWashout::LimitedTilt(int axis, double wanted_rad) {
  const auto i = static_cast<std::size_t>(axis);
  double& tilt = tilt_rad_[i];
  double& rate = tilt_rate_rad_s_[i];
  const double accel = parameters_.tilt_accel_max_rad_s2;
  // The target's own rate, and on top of it the rate that closes the gap
  // left to where the target was, in one cycle, at most the rate from
  // which the acceleration limit still stops on it: within the limits the
  // tilt is the target, exactly (the gap to the new target would count the
  // target's step twice and run a cycle ahead).
  const double error = last_wanted_rad_[i] - tilt;
  const double target_rate = (wanted_rad - last_wanted_rad_[i]) / period_s_;
  last_wanted_rad_[i] = wanted_rad;
  const double closing_max = std::sqrt(2.0 * accel * std::fabs(error));
  const double closing = std::clamp(error / period_s_, -closing_max, closing_max);
  const double wanted_rate =
      std::clamp(target_rate + closing, -parameters_.tilt_rate_max_rad_s, parameters_.tilt_rate_max_rad_s);
  rate += std::clamp(wanted_rate - rate, -accel * period_s_, accel * period_s_);
  tilt += rate * period_s_;
  return tilt;
}

HeadCue ClassicalWashout::Step(const VehicleSample& sample) {
  const auto& p = parameters_;
  // A value that is not finite would stay in the filters' states for good.
  if (!sample.specific_force_m_s2.allFinite() || !sample.angular_velocity_rad_s.allFinite()) {
    throw std::invalid_argument(fmt::format("washout: the vehicle sample at t = {} s is not finite", sample.t_s));
  }
  // The rider at rest feels gravity: only the departure from it is cued.
  Vector3 force = sample.specific_force_m_s2 - Vector3(0.0, 0.0, kStandardGravity_m_s2);
  HeadCue cue;
  for (int axis = 0; axis < 3; ++axis) {
    cue.position_m(axis) = translation_[static_cast<std::size_t>(axis)]->Step(force(axis));
    cue.rpy_rad(axis) = rotation_[static_cast<std::size_t>(axis)]->Step(sample.angular_velocity_rad_s(axis));
  }
  // Tilt coordination: gravity along a tilted head is −g sin(pitch) on x
  // and g sin(roll) on y (z up).
  const double tilt_limit = std::sin(p.tilt_max_rad);
  const double fx = tilt_[1]->Step(p.specific_force_scale * force.x()) / kStandardGravity_m_s2;
  const double fy = tilt_[0]->Step(p.specific_force_scale * force.y()) / kStandardGravity_m_s2;
  cue.rpy_rad(0) += LimitedTilt(0, std::asin(std::clamp(fy, -tilt_limit, tilt_limit)));
  cue.rpy_rad(1) += LimitedTilt(1, -std::asin(std::clamp(fx, -tilt_limit, tilt_limit)));
  return cue;
}

void ClassicalWashout::Reset() { *this = ClassicalWashout(parameters_, period_s_); }

Pose CueToPlatformPose(const Pose& neutral, const Vector3& head_in_platform_m, const HeadCue& cue) {
  const Vector3 neutral_head = PointInBase(neutral, head_in_platform_m);
  Pose pose;
  pose.rpy_rad = neutral.rpy_rad + cue.rpy_rad;
  pose.p_BoMo_B = neutral_head + cue.position_m - RotationFromRpy(pose.rpy_rad) * head_in_platform_m;
  return pose;
}

}  // namespace edsp
