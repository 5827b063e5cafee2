#pragma once
// How well a motion set lets edsp-gap identify the leg-error vocabulary
// (kinematics/leg_error_model.h): the identification Jacobian of the
// tracker's point A with respect to every effect's parameters, sampled
// along the trajectory as a tracker would, with the tracker's frame (a
// nuisance the diagnosis estimates too) projected out.
//
// Each parameter is scaled by its typical size on a real rig and each row by
// the tracker's noise, so a singular value σ says: along that parameter
// direction, the motion set resolves the typical size σ times over (its
// standard deviation is 1/σ typical sizes). Reported, after Sun &
// Hollerbach and Borm & Menq:
//   condition  σmax/σmin
//   O1         (σ1·…·σm)^(1/m) / √samples   (D-optimality, per sample)
//   O3         σmin                          (the worst direction, whole run)

#include <string>
#include <vector>

#include <Eigen/Core>

#include "edsp/kinematics/leg_error_model.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/trajectory.h"

namespace edsp {

struct IdentifiabilityOptions {
  double rate_hz = 100.0;            // tracker samples per second
  double noise_sigma_m = 5e-6;       // tracker noise per axis
  PrMode pr_mode = PrMode::kSigned;  // the compensation the commands carry
  calibration::LegErrorOptions errors;
};

// The effects judged together: every effect but leg_offset, which is a
// special case of joint_position (identified apart, never beside it).
std::vector<calibration::Effect> JointlyIdentifiedEffects();

using calibration::PointSensitivity;

// calibration::PointSensitivityAt; throws std::invalid_argument naming a
// singular pose.
PointSensitivity PointSensitivityAt(const PlatformModel& model, const Pose& pose);

// Fisher information of [frame (6) | parameters of `effects`], in the
// scaled units above, accumulated sample by sample.
class IdentificationInformation {
 public:
  IdentificationInformation(const PlatformModel& model, std::vector<calibration::Effect> effects,
                            const IdentifiabilityOptions& options);
  // Adds one tracker sample of point A with the legs' error state.
  void Add(const PointSensitivity& at, const calibration::LegErrorState& state);
  // The information about the parameters once the frame is estimated too
  // (the Schur complement of the frame block).
  Eigen::MatrixXd ParameterInformation() const;
  // All of it, frame first (symmetric).
  Eigen::MatrixXd Full() const { return information_.selfadjointView<Eigen::Lower>(); }
  int samples() const { return samples_; }
  int parameters() const { return static_cast<int>(information_.rows()) - 6; }

 private:
  const PlatformModel* model_;
  std::vector<calibration::Effect> effects_;
  std::vector<Eigen::MatrixXd> scale_;  // per effect: raw parameters → scaled, reduced
  double row_scale_;
  Eigen::MatrixXd information_;
  int samples_ = 0;
};

struct Identifiability {
  std::string effects;  // an effect's name, or "all"
  int parameters = 0;
  int samples = 0;
  double condition = 0.0;
  double o1 = 0.0;
  double o3 = 0.0;
};

// What the leg-error model needs at time t of a trajectory: the commanded
// legs (inverse kinematics less the PR compensation of `pr_mode`) and their
// rates by central differences of the trajectory itself (1 ms apart).
calibration::LegErrorInputs ErrorInputsAt(const PlatformModel& model, const Trajectory& trajectory, double t_s,
                                          PrMode pr_mode);

Identifiability Summarize(const std::string& name, const IdentificationInformation& information);

// Samples the trajectory at the tracker's rate, following the legs' error
// state (play, heat) in time order, and judges each effect alone and
// JointlyIdentifiedEffects() together ("all", the first row).
std::vector<Identifiability> AssessIdentifiability(const PlatformModel& model, const Trajectory& trajectory,
                                                   const IdentifiabilityOptions& options);

}  // namespace edsp
