#include "edsp/kinematics/structural_mode.h"

#include <cmath>

namespace edsp {

namespace {
constexpr double kTwoPi = 6.283185307179586;
// Integration steps per period of the mode: semi-implicit Euler keeps a
// lightly damped oscillator's energy, and 1/64 of a period puts its
// frequency within 0.1%.
constexpr double kStepsPerPeriod = 64.0;
}  // namespace

StructuralMode::StructuralMode(double hz, double damping, const Vector3& mass)
    : omega_(kTwoPi * hz), damping_(damping), mass_(mass) {}

void StructuralMode::Reset() {
  x_.setZero(), v_.setZero();
  started_ = false;
}

const Vector3& StructuralMode::Advance(double dt_s, const Vector3& accel) {
  const double period = kTwoPi / omega_;
  if (!started_ || !(dt_s >= 0.0) || dt_s > kForgetAfterPeriods * period) {
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
