#pragma once
// The leg-space error model that edsp-gap fits and a calibration applies:
// at each instant, the state every effect's leg-length error depends on
// (stroke, its derivatives, the gearbox play, the screws' heat, the legs'
// loads) and each effect's basis B_e(state), so that the legs are longer
// than the nominal model believes by Δl = Σ_e B_e·θ_e. One implementation
// for both: a calibration compensates exactly what the diagnosis identified.

#include <optional>

#include <Eigen/Core>

#include "edsp/kinematics/leg_effects.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/kinematics/structural_mode.h"

namespace edsp::calibration {

struct LegErrorOptions {
  double thermal_time_constant_s = 900.0;  // cooling of the screws
  double backlash_width_m = 30e-6;         // play the backlash basis's operator assumes
  double structural_mode_hz = 0.0;         // the structural mode's frequency (0: none, a zero basis)
  double structural_mode_damping = 0.03;   //   and damping ratio ζ
  Vector3 gravity_B_m_s2 = Vector3(0.0, 0.0, -9.81);
};

// One instant as the error model needs it.
struct LegErrorInputs {
  double time_s = 0.0;
  Pose pose;                            // of {M} in {B}: commanded, or where the encoders put it
  Vector6 command_m = Vector6::Zero();  // where the screw is sent (encoder-length units): the stroke
  Vector6 motor_m = Vector6::Zero();    // what drives the play: the encoders' length, or the command
  Vector6 velocity = Vector6::Zero(), accel = Vector6::Zero(), jerk = Vector6::Zero();  // of the command
  Vector3 platform_accel_B_m_s2 = Vector3::Zero();
  Vector3 point_accel_B_m_s2 = Vector3::Zero();  // of A along the commands (drives the structural mode)
};

struct LegErrorState {
  LegSolution legs;
  Vector6 stroke, velocity, accel, jerk, play, heat, pr_signed, compensation;
  double warm = 0.0;                        // time under power, decayed with the screws' cooling (s)
  Eigen::Matrix<double, 6, 4> load;         // leg forces per kg at {M}'s origin, then per kg·m of c.o.m. x, y, z
  Vector3 sway = Vector3::Zero();           // the structural mode's response at unit gain (structural_mode.h)
  Eigen::Matrix<double, 6, 3> translation;  // leg lengths (IK − PR) per translation of {M} along x, y, z
};

// Follows the state that carries over from instant to instant (the play
// operator of each gearbox, homed extending; the screws' heat from travel
// and from time under power), in time order.
class LegErrorTracker {
 public:
  LegErrorTracker(PlatformModel model, LegErrorOptions options);
  LegErrorState Advance(const LegErrorInputs& in);
  const LegErrorOptions& options() const { return options_; }

 private:
  PlatformModel model_;
  LegErrorOptions options_;
  Vector6 driven_, heat_ = Vector6::Zero(), last_stroke_ = Vector6::Zero();
  double warm_ = 0.0, last_time_s_ = 0.0;
  bool first_ = true;
  std::optional<StructuralMode> mode_;
};

// Where the tracker's point A is at a pose and how it moves with the legs'
// lengths, ∂A/∂q · (∂l/∂q)⁻¹ with the screws following the true signed PR:
// what turns a leg-space error into a point-A error.
struct PointSensitivity {
  Vector3 point = Vector3::Zero();
  Eigen::Matrix<double, 3, 6> per_leg = Eigen::Matrix<double, 3, 6>::Zero();
};
// False (and *out untouched) where the pose is singular for the model.
bool PointSensitivityAt(const PlatformModel& model, const Pose& pose, PointSensitivity* out);

// [v]×: the cross product with v as a matrix.
Matrix3 Skew(const Vector3& v);

// Leg lengths (IK − PR) per translation of {M}: the legs' change that moves
// A by a vector, whatever the pose's rotation.
Eigen::Matrix<double, 6, 3> TranslationToLegs(const PlatformModel& model, const Pose& pose);

// Leg-space basis B_e (6 × ParameterCount(e)) of one effect at one state.
Eigen::MatrixXd LegErrorBasis(Effect effect, const LegErrorState& state, const PlatformModel& model);

}  // namespace edsp::calibration
