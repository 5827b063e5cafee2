#include "edsp/kinematics/structural_mode.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edsp {

namespace {
// Integration steps per period of the mode: semi-implicit Euler keeps a
// lightly damped oscillator's energy, and 1/64 of a period puts its
// frequency within 0.1%.
constexpr double kStepsPerPeriod = 64.0;
}  // namespace

StructuralMode::StructuralMode(double hz, double damping, const Vector3& mass)
    : omega_(kTwoPi * hz), damping_(damping), mass_(mass) {
  if (!(hz > 0.0 && std::isfinite(hz)) || !(damping >= 0.0 && damping <= 1.0) || !(mass.minCoeff() > 0.0)) {
    throw std::invalid_argument("StructuralMode: needs hz > 0, damping in [0, 1] and a positive mass");
  }
  // A lighter mass rings faster (ω/√m): the steps follow the fastest axis.
  step_omega_ = omega_ / std::sqrt(mass_.minCoeff());
  // Rung out to 1e-4 of itself: e^(−ζω·t) = 1e-4, and never under 50 periods.
  forget_after_s_ = std::max(kForgetAfterPeriods * kTwoPi / omega_, std::log(1e4) / std::max(damping_ * omega_, 1e-9));
}

void StructuralMode::Reset() {
  x_.setZero(), v_.setZero();
  started_ = false;
}

const Vector3& StructuralMode::Advance(double dt_s, const Vector3& accel) {
  const double period = kTwoPi / step_omega_;
  if (!started_ || !(dt_s >= 0.0) || dt_s > forget_after_s_) {
    x_.setZero(), v_.setZero();
    started_ = true;
    last_accel_ = accel;
    return x_;
  }
  const int steps = static_cast<int>(std::ceil(dt_s * kStepsPerPeriod / period));
  const double h = steps > 0 ? dt_s / steps : 0.0;
  for (int s = 0; s < steps; ++s) {
    const double w = (s + 0.5) / steps;  // the acceleration linear over the span
    const Vector3 a = (1.0 - w) * last_accel_ + w * accel;
    const Vector3 force = -a - omega_ * omega_ * x_ - 2.0 * damping_ * omega_ * v_;
    v_ += h * force.cwiseQuotient(mass_);
    x_ += h * v_;
  }
  last_accel_ = accel;
  return x_;
}

}  // namespace edsp
