#pragma once
// A calibration: the effects edsp-gap identified (its `edsp-gap-model/1`
// file, `diagnose --save-model`), checked against the platform it is to run
// on, and applied to the leg commands so that the platform lands where the
// nominal model says (docs/calibration.md).

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "edsp/kinematics/leg_error_model.h"
#include "edsp/kinematics/verdict.h"

namespace edsp::calibration {

// A model file that cannot be read, or does not fit the platform; the
// message names the file and the key.
class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CalibratedEffect {
  Effect effect = Effect::kLegOffset;
  Eigen::VectorXd theta;
  Verdict verdict = Verdict::kIdentified;  // the file's (none: identified); applied as AppliesEntry says
  bool has_apply = false, apply = false;   // the file's "apply", if it has one
};

struct CalibrationModel {
  std::string origin;       // the file
  std::string hash;         // FNV-1a 64 of its bytes, hex
  LegErrorOptions options;  // thermal time constant, backlash width
  std::vector<CalibratedEffect> applied;
  std::vector<std::string> not_applied;  // "name (why)"
  // "<file> <hash>: applies a, b; not applied: c (ambiguous)"
  std::string Describe() const;
};

// Reads and checks a model: its format, every effect's name, parameter
// count and finiteness, each parameter within what a real platform can
// have (docs/calibration.md), and, where the file records it, the platform
// it was identified on against `model`. Which entries are applied:
// AppliesEntry. Throws CalibrationError.
CalibrationModel LoadCalibration(const std::string& path, const PlatformModel& model, bool apply_ambiguous = false);
CalibrationModel ParseCalibration(const std::string& text, const std::string& origin, const PlatformModel& model,
                                  bool apply_ambiguous = false);

// Refuses (CalibrationError, naming the leg and the size) a calibration
// that would command a leg outside its stroke at home: no correction of a
// real platform comes near that. ParseCalibration checks it.
void RequireWithinTheStrokes(const CalibrationModel& calibration, const PlatformModel& model);

// Whether a model file's entry is applied: as its "apply" says when it has
// one (edsp-gap's calibration set: the effects that best predict held-out
// error, named or not), else when it is identified; an ambiguous entry also
// when `apply_ambiguous`.
bool AppliesEntry(Verdict verdict, bool has_apply, bool apply, bool apply_ambiguous);

// The θ of an effect the LegCompensator does not apply (the servo lag's
// jerk term: a trapezoid's corners would make it a spike): data recorded
// with a calibration in force still holds their part of the leg error.
std::vector<int> UnappliedParameters(Effect effect);

// What a model file records of the platform it was identified on, so that
// it is refused on another.
std::string PlatformFingerprint(const PlatformModel& model);

// Turns a calibration into command corrections, one control cycle at a
// time: the leg error Δl the model predicts for the commanded state (its
// play, heat and loads followed from command to command), which the
// command subtracts. The command's rates come from the setpoint's
// velocity and acceleration (no differencing of the command); the
// correction changes at most kMaxCorrectionRate_m_s, so a jump in the
// setpoint's rates cannot make the command step.
class LegCompensator {
 public:
  LegCompensator(PlatformModel model, CalibrationModel calibration);

  struct Correction {
    Vector6 command_m = Vector6::Zero();  // subtract from the command
    Vector6 encoder_m = Vector6::Zero();  // add to the encoders' lengths for forward kinematics
                                          // (every effect but the servo's lag, which the encoders see)
  };
  // `command_m`: the nominal command (IK length − PR correction).
  Correction Step(double time_s, const Pose& pose, const Vector6& pose_velocity, const Vector6& pose_acceleration,
                  const Vector6& command_m);
  const CalibrationModel& calibration() const { return calibration_; }

  static constexpr double kMaxCorrectionRate_m_s = 0.05;
  // The structural mode's inverse (structural_mode.h) needs 1 − g > 0: a
  // gain beyond 1 − kMinModeMass is compensated as if it were that (the
  // inverse of a mode with that gain: the sway in part).
  static constexpr double kMinModeMass = 0.25;

 private:
  Vector6 StructuralSway(const CalibratedEffect& e, double time_s, const LegErrorInputs& in);

  PlatformModel model_;
  CalibrationModel calibration_;
  LegErrorTracker tracker_;                     // without the structural mode (it integrates the inverse below)
  std::optional<StructuralMode> inverse_mode_;  // the sway the command cancels
  double last_mode_time_s_ = 0.0;
  std::optional<double> last_time_s_;
  Vector6 last_command_m_ = Vector6::Zero();
};

}  // namespace edsp::calibration
