#pragma once
// A lightly damped mode of the structure that carries point A (the
// platform's top frame, the tracker's reflector mount): the sway x of A,
// per axis of {B}, relative to the rigid platform, driven by A's
// acceleration a as a mass on a spring is by its base's:
//   m·ẍ + 2ζω·ẋ + ω²·x = −a.
// m = 1 is the mode itself (what the diagnosis fits, scaled by a gain g per
// axis: the sway is g·x). A calibration that moves the legs to cancel the
// sway changes the acceleration that drives it; the sway it must cancel
// then follows m = 1 − g (leg_error_model.h, calibration.h).
// One implementation for the diagnosis's basis, the calibration and the
// virtual rig's physics.

#include "edsp/kinematics/types.h"

namespace edsp {

class StructuralMode {
 public:
  // `hz` > 0; `damping` ζ in [0, 1]; `mass` per axis > 0 (std::invalid_argument otherwise).
  StructuralMode(double hz, double damping, const Vector3& mass = Vector3::Ones());

  // The sway at an instant `dt_s` after the last, given A's acceleration
  // there; the acceleration is taken as linear in between. A first call, a
  // step back in time, or a gap in which the mode has rung out (to 1e-4 of
  // itself, and at least kForgetAfterPeriods periods) starts again from rest.
  const Vector3& Advance(double dt_s, const Vector3& accel);
  void Reset();
  const Vector3& sway() const { return x_; }

  // At ζ 0.03 a mode has decayed to 1e-4 of itself after 50 periods.
  static constexpr double kForgetAfterPeriods = 50.0;

 private:
  double omega_, damping_;
  Vector3 mass_;
  double step_omega_ = 0.0, forget_after_s_ = 0.0;
  Vector3 x_ = Vector3::Zero(), v_ = Vector3::Zero(), last_accel_ = Vector3::Zero();
  bool started_ = false;
};

}  // namespace edsp
