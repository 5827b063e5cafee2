#pragma once
// The linearised measurement model every fit of the diagnosis shares.
// At each row n the nominal model puts point A at A_n = A(pose_n), the
// commanded pose, or with encoder columns the pose the nominal model reaches
// with the legs behind their commands by what the encoders recorded (the
// lag's linear part, G_n·(enc − cmd), is added back to r for servo_lag); leg
// errors Δl move it by G_n·Δl with G_n = ∂A/∂q·(∂l/∂q − ∂PR/∂q)⁻¹; the tracker
// sees it through its frame, T(p) = R·p + t. Around a first frame estimate
// (R0, t0, Umeyama) the residual r_n = point_n − (R0·A_n + t0) is linear in
// the frame correction (δt, δω) and in every effect's parameters θ:
//   r_n ≈ δt − R0[A_n]×·δω + Σ_e R0·G_n·B_e,n·θ_e.
// Rows are stored grouped by run (each run a contiguous block). With encoder
// columns, the drives' following error that servo_lag's terms cannot
// describe is taken out of r as the encoders measured it, where it stands
// above the tracker's noise.

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/effects.h"
#include "edsp/diagnosis/measurement_data.h"
#include "edsp/kinematics/leg_error_model.h"
#include "edsp/kinematics/passive_rotation.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::gap {

// The error model's settings (Diagnose refits the backlash width and the
// thermal time constant to their estimates).
using DesignOptions = calibration::LegErrorOptions;

struct ColumnRange {
  int begin = 0, count = 0;
};

struct Design {
  // Rows (3 per sample), grouped by run.
  Eigen::VectorXd residual;                      // r, m
  Eigen::MatrixXd columns;                       // [frame (6) | nuisance | every effect's θ columns]
  ColumnRange frame;                             // δt (3), δω (3)
  ColumnRange nuisance;                          // estimated with the frame in every fit (none unless WithNuisance)
  std::array<ColumnRange, kEffectCount> effect;  // by static_cast<int>(Effect)
  std::vector<int> sample_run;                   // run of each sample
  std::vector<ColumnRange> run_samples;          // samples of each run (contiguous)
  std::vector<std::string> runs;
  std::vector<int> source_row;  // row in MeasurementData of each sample

  // Per sample, for the gap summaries.
  std::vector<Eigen::Matrix<double, 3, 6>> point_per_leg;  // R0·G_n
  std::vector<Vector3> model_point;                        // A_n in {B}
  std::vector<Vector6> leg_velocity_m_s;
  std::vector<Vector6> leg_accel_m_s2;
  std::vector<Vector3> point_accel_m_s2;  // A's, in {B}, along the commands (0 at a run's ends)
  // The moment about {B}'s origin of 1 kg's weight and translational
  // inertia at {M}'s origin (N·m/kg), then per kg·m of c.o.m. offset along
  // {M}'s x, y, z (N/kg); the platform's rotational inertia is left out.
  std::vector<Eigen::Matrix<double, 3, 4>> load_moment_per_kg;
  // leg_cmd − leg_enc, when the data has encoders: the part servo_lag's
  // terms describe (the rest is taken out of the residual: BuildDesign).
  std::vector<Vector6> servo_error_m;
  // At A, RMS over the samples: the drives' error beyond servo_lag's terms
  // (taken out of the residual when above the tracker's noise per axis),
  // and the part servo_lag's terms describe.
  double drives_rest_rms_m = 0.0, drives_described_rms_m = 0.0;
  bool drives_rest_taken_out = false;
  std::vector<double> time_s;
  std::vector<double> displacement;  // |pose − home| (m, rad mixed: metres + 1 m per rad)
  bool has_encoder = false;

  // The PR compensation the data's controller applied (IK length − command)
  // against the signed PR model: least-squares ratio κ, and a name for it.
  double applied_pr_ratio = 0.0;
  std::optional<PrMode> applied_pr = PrMode::kNone;  // none of edsp's modes: nullopt

  // Frame estimate the residual is taken around: point = R0·A + t0.
  Matrix3 R0 = Matrix3::Identity();
  Vector3 t0 = Vector3::Zero();

  int samples() const { return static_cast<int>(sample_run.size()); }
  int parameters() const { return static_cast<int>(columns.cols()); }
  const ColumnRange& Of(Effect e) const { return effect[static_cast<std::size_t>(e)]; }
};

// Point noise floor (RMS of |noise| at A) from sample-to-sample differences
// of the residual where the platform is at rest.
double NoiseFloorRms(const Design& design);

// r with the drives' following error as the encoders recorded it (servo
// error, seen at A) set aside: the residual about the pose the legs stood
// at, in which a soft loop's millimetres are motion, not misfit. r itself
// without encoder columns.
Eigen::VectorXd ResidualWhereTheLegsStood(const Design& design);

// The applied compensation's name in reports: a PR mode's, or "other".
const char* AppliedPrName(const std::optional<PrMode>& applied);

// Throws MeasurementError if a commanded pose is outside what the model can
// solve (names the run and time).
Design BuildDesign(const PlatformModel& model, const MeasurementData& data, const DesignOptions& options = {});

// Every member of `d` but its columns and its nuisance's range, copied: the
// columns, the large part, are built for the new design, not copied and
// then rebuilt.
Design WithoutColumns(const Design& d);

// `d` with only the frame, its nuisance and the listed effects' columns.
Design KeepOnly(const Design& d, const std::vector<Effect>& keep);

// Rigid frame (R, t) with measured ≈ R·model + t, least squares (Umeyama).
void EstimateFrame(const std::vector<Vector3>& model_points, const std::vector<Vector3>& measured, Matrix3* R,
                   Vector3* t);

// Whether the points fix a rigid frame's rotation about every axis: they
// spread over a plane or more (the second of their principal RMS spreads at
// least `min_spread_m`). A rotation about point A itself leaves A where it
// is, a line leaves the rotation about that line free: the frame estimated
// on such data is arbitrary about those axes.
bool FixesFrameRotation(const std::vector<Vector3>& points, double min_spread_m = 5e-3);

// The residual once a prediction of the effects (`predicted_B`: 3 rows a
// sample, A's displacement in {B}) is taken off, the prediction turned into
// the tracker's frame by `R` (a frame the data cannot fix: the fit's) and
// the translation fitted.
Eigen::VectorXd ResidualInFrame(const Design& d, const Matrix3& R, const Eigen::VectorXd& predicted_B);

}  // namespace edsp::gap
