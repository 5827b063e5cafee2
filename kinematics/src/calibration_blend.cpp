#include "edsp/kinematics/calibration_blend.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace edsp::calibration {

namespace {
LegCompensator::Correction StepOrZero(LegCompensator* compensator, double time_s, const Pose& pose,
                                      const Vector6& velocity, const Vector6& acceleration, const Vector6& command_m) {
  if (compensator == nullptr) return {};
  return compensator->Step(time_s, pose, velocity, acceleration, command_m);
}
}  // namespace

CalibrationBlend::CalibrationBlend(std::unique_ptr<LegCompensator> in_force, std::int64_t blend_us)
    : next_(std::move(in_force)), blend_us_(std::max<std::int64_t>(blend_us, 1)), running_us_(blend_us_) {}

bool CalibrationBlend::SwitchTo(std::unique_ptr<LegCompensator> next, std::string* why_not) {
  if (blending_) {
    const double left_ms = (static_cast<double>(running_us_) - elapsed_us_) * 1e-3;
    *why_not = fmt::format("the last switch is still blending ({:.0f} of {} ms of setpoint time left)",
                           std::ceil(left_ms), running_us_ / 1000);
    return false;
  }
  previous_ = std::move(next_);
  next_ = std::move(next);
  blending_ = true;
  running_us_ = blend_us_;
  elapsed_us_ = 0.0;
  return true;
}

void CalibrationBlend::BlendInFrom(double weight, std::int64_t blend_us) {
  if (!next_ || blending_ || !(weight < 1.0)) return;
  previous_.reset();
  blending_ = true;
  running_us_ = std::max<std::int64_t>(blend_us, 1);
  elapsed_us_ = std::clamp(weight, 0.0, 1.0) * static_cast<double>(running_us_);
}

double CalibrationBlend::AdvanceBlend(std::int64_t setpoint_utime) {
  // In double: the stamps may be any int64, and their difference overflow.
  const double since_last =
      last_setpoint_utime_ ? static_cast<double>(setpoint_utime) - static_cast<double>(*last_setpoint_utime_) : 0.0;
  last_setpoint_utime_ = setpoint_utime;
  if (!blending_) return 1.0;
  elapsed_us_ += std::clamp(since_last, 0.0, kMaxAdvance_us);
  if (elapsed_us_ >= static_cast<double>(running_us_)) {
    blending_ = false;
    previous_.reset();
    return 1.0;
  }
  return elapsed_us_ / static_cast<double>(running_us_);
}

LegCompensator::Correction CalibrationBlend::Step(std::int64_t setpoint_utime, const Pose& pose,
                                                  const Vector6& pose_velocity, const Vector6& pose_acceleration,
                                                  const Vector6& command_m) {
  const double time_s = static_cast<double>(setpoint_utime) * 1e-6;
  // Both run every cycle of a blend: each follows the commands (its play,
  // its heat) as if it were alone, and only their outputs are mixed.
  const LegCompensator::Correction from =
      StepOrZero(blending_ ? previous_.get() : nullptr, time_s, pose, pose_velocity, pose_acceleration, command_m);
  const LegCompensator::Correction to =
      StepOrZero(next_.get(), time_s, pose, pose_velocity, pose_acceleration, command_m);
  const double a = AdvanceBlend(setpoint_utime);
  if (a >= 1.0) return to;
  LegCompensator::Correction mixed;
  mixed.command_m = (1.0 - a) * from.command_m + a * to.command_m;
  mixed.encoder_m = (1.0 - a) * from.encoder_m + a * to.encoder_m;
  return mixed;
}

}  // namespace edsp::calibration
