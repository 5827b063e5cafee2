#pragma once
// Classical washout (Reid & Nahon 1985; docs/cueing.md, "Classical
// washout"): the baseline every cueing algorithm is compared with.
//   translation, per axis:  x(s) / f(s) = k_f s / ((s² + 2ζ ωn s + ωn²)(s + ωb))
//     (the scaled specific force high-passed to third order and integrated
//     twice: onsets are felt, sustained force washes out to neutral);
//   tilt coordination, x and y: the low-passed scaled specific force taken
//     up by tilting the rider in gravity, pitch = −asin(fx/g),
//     roll = asin(fy/g), at most tilt_rate_max (at the canals'
//     threshold, so the tilt itself is barely felt as a rotation) and
//     tilt_accel_max (a rate limit alone steps the tilt's rate, and the
//     legs' acceleration with it: up to 122 m/s² in one 1 ms cycle on the
//     paper's platform);
//   rotation, per axis:  angle(s) / ω(s) = k_ω s / (s² + 2ζ ω s + ω²)
//     (the scaled angular velocity high-passed to second order and integrated).
// Its output is the rider's head pose relative to the neutral one; the
// platform pose that puts the head there is CueToPlatformPose's.

#include <array>
#include <optional>

#include "edsp/cueing/linear_filter.h"
#include "edsp/cueing/vehicle_motion.h"
#include "edsp/kinematics/pose.h"

namespace edsp {

struct ClassicalWashoutParameters {
  double specific_force_scale = 0.5;                           // k_f
  double angular_velocity_scale = 0.5;                         // k_ω
  Vector3 translation_break_rad_s = Vector3(2.5, 2.5, 4.0);    // ωn
  double translation_damping = 1.0;                            // ζ
  Vector3 translation_washout_rad_s = Vector3(0.5, 0.5, 1.0);  // ωb
  double tilt_break_rad_s = 5.0;                               // the tilt's second-order low-pass
  double tilt_damping = 1.0;
  double tilt_rate_max_rad_s = 3.0 * kPi / 180.0;
  double tilt_accel_max_rad_s2 = 0.5;
  double tilt_max_rad = 15.0 * kPi / 180.0;
  Vector3 rotation_break_rad_s = Vector3(1.0, 1.0, 1.0);
  double rotation_damping = 1.0;
};

// Throws std::invalid_argument naming the parameter that is absurd
// (a break frequency ≤ 0, a scale outside (0, 1], a rate limit ≤ 0, …).
void ValidateWashout(const ClassicalWashoutParameters& parameters);

// The head's displacement from its neutral pose: position in {B} (m) and
// roll, pitch, yaw (rad).
struct HeadCue {
  Vector3 position_m = Vector3::Zero();
  Vector3 rpy_rad = Vector3::Zero();
};

class ClassicalWashout {
 public:
  ClassicalWashout(const ClassicalWashoutParameters& parameters, double period_s);
  // Throws std::invalid_argument for a sample that is not finite (the
  // packet parser and the input guard refuse one before it gets here).
  HeadCue Step(const VehicleSample& sample);
  // Back at the neutral pose with a rider at rest, as when made.
  void Reset();
  const ClassicalWashoutParameters& parameters() const { return parameters_; }

 private:
  // The tilt moved towards `wanted_rad` as fast as its rate and
  // acceleration limits allow, braking in time to stop on it; within the
  // limits, `wanted_rad` itself.
  double LimitedTilt(int axis, double wanted_rad);

  ClassicalWashoutParameters parameters_;
  double period_s_;
  std::array<std::optional<DiscreteFilter>, 3> translation_;
  std::array<std::optional<DiscreteFilter>, 2> tilt_;
  std::array<std::optional<DiscreteFilter>, 3> rotation_;
  std::array<double, 2> tilt_rad_{};  // roll, pitch of the tilt coordination
  std::array<double, 2> tilt_rate_rad_s_{};
  std::array<double, 2> last_wanted_rad_{};
};

// The platform pose ({M} in {B}) that puts a head at `head_in_platform_m`
// (in {M}) at the neutral head pose displaced by `cue`.
Pose CueToPlatformPose(const Pose& neutral, const Vector3& head_in_platform_m, const HeadCue& cue);

}  // namespace edsp
