#pragma once
// edsp-gap diagnose: where the gap between the model and the measurement
// lies, which effects of the vocabulary explain it (forward selection with
// cross-validation across runs and an information criterion), how far it
// shrinks on runs held out of every fit, and what is left.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/change_point.h"
#include "edsp/diagnosis/chosen_by.h"
#include "edsp/diagnosis/conclusion.h"
#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/gap_summary.h"
#include "edsp/diagnosis/recorded_correction.h"
#include "edsp/diagnosis/residual_structure.h"
#include "edsp/diagnosis/time_offset.h"
#include "edsp/diagnosis/whiteness.h"

namespace edsp::gap {

struct DiagnoseOptions {
  double max_rate_hz = 100.0;  // rows per run are thinned to this rate
  // Data recorded with a calibration in force (leg_corr_*_m): the rig's
  // whole effects (nominal) or what the calibration leaves (recorded_correction.h).
  Against against = Against::kNominal;
  DesignOptions design;
  double min_cv_gain = 0.05;     // an effect must cut the held-out MSE by this fraction
  double min_bic_drop = 10.0;    // and lower BIC by this much
  double ambiguity_ratio = 0.7;  // an alternative reaching this share of its gain is as good
  double significance = 0.05;    // and beat the model without it run by run (paired t-test, one-sided)
  double nested_gain = 0.05;     // a richer effect replaces the simpler one it contains only
                                 // if it cuts the held-out MSE by this fraction more
  int max_effects = 10;
  // When thermal drift is found, its time constant is chosen among these by
  // the held-out error (empty: design.thermal_time_constant_s as given).
  std::vector<double> thermal_time_constants_s = {150.0, 300.0, 600.0, 1200.0, 2400.0, 4800.0};
  // Whether to search for a structural mode (structural_mode_fit.h) when
  // design.structural_mode_hz is 0; a given frequency is used as it is.
  bool fit_structural_mode = true;
  StructureOptions structure;  // when what is left counts as structure (unknown)
  // Whether one rig explains the session, asked first (change_point.h):
  // with a change found, the rest diagnoses the rig after it.
  ChangePointOptions changes;
};

struct EffectResult {
  Effect effect = Effect::kLegOffset;
  Eigen::VectorXd theta, sigma;     // fitted on every run, with 1-σ uncertainties
  double explained_fraction = 0.0;  // of the gap's variance, in selection order
  double cv_gain = 0.0;             // held-out MSE reduction / baseline held-out MSE
  Verdict verdict = Verdict::kRejected;
  std::vector<Effect> ambiguous_with;   // the effects it ties with (Verdicts),
  bool ambiguous_with_unknown = false;  //   and whether something beyond the vocabulary does (beyond_vocabulary.h),
  // only as a stand-in for the platform's own mechanics (a base tilting in
  // its place): a calibration may apply it, since it moves the platform as
  // that would; not for a clock, a lag after the motor or bare structure.
  bool stands_in_for_mechanics = false;
  std::string next_measurement;
  double frame_overlap = 0.0;    // share of its signature the tracker frame can mimic
  double max_correlation = 0.0;  // strongest |correlation| of a parameter with another
  std::string correlated_with;   //   selected effect's or the frame's (selected effects)
  bool encoder_checked = false;  // selected servo_lag with encoders:
  double encoder_share = 0.0;    //   the share of it they show (encoder_check.h)
};

// What an effect is ambiguous with, as the report names it: the effects,
// then `unknown` (the checks beyond the vocabulary run after the verdicts).
std::vector<std::string> AmbiguousWithNames(const EffectResult& r);

// One sample's gap at A before and after the selected effects (in-sample),
// for the report's plots.
struct SampleGap {
  int run = 0;
  double time_s = 0.0, displacement = 0.0, before_m = 0.0, after_m = 0.0;
};

// Whether the base tilts under the payload's moment (structure_nuisance.h's
// BaseTiltColumns), which no effect of the vocabulary models: tested when
// an effect it resembles is selected (compliance, joint_position), beside
// the selected effects and in place of those it resembles.
struct BaseTiltCheck {
  bool tested = false;
  double cv_gain = 0.0;           // the tilt's cut of the selected model's held-out MSE
  bool tilts = false;             // by min_cv_gain and run by run: something beyond the vocabulary
  double in_place_cv_gain = 0.0;  // the same cut with the tilt in place of compliance and joint_position
  double in_place_share = 0.0;    // of their held-out gain, the share the tilt takes up in their place
  bool replaces = false;          // not `tilts`, but in their place it ties with them as effects tie (Verdicts)
};

// Whether the tracker's clock drifts from the controller's
// (time_offset.h's DriftingOffsetColumns), which no effect models: tested
// in every diagnosis, beside the selected effects and, without encoders, a
// constant offset (with them, the drift about the encoders' offset;
// beyond_vocabulary.h).
struct ClockDriftCheck {
  bool tested = false;
  double drift = 0.0, sigma = 0.0;  // ρ (s/s; 1e-6 = 1 ppm, the tracker's clock gaining) and its 1-σ
  double cv_gain = 0.0;             // the drift's cut of the held-out MSE beside the selected effects (and the offset)
  bool run_by_run = false;          // |ρ| > 5σ and a cut every held-out run shows (the paired test)
  bool drifts = false;              // and the cut is min_cv_gain or a selected effect no longer earns its place beside
                                    // the drifting clock: something beyond the vocabulary
};

// Without encoders, whether a selected servo_lag is no more than the
// tracker's clock running a constant δ ahead: the offset's column
// (time_offset.h) beside the other selected effects predicts the held-out
// runs as well, run by run (beyond_vocabulary.h). A drive's loop lags
// acceleration differently from a delay, and legs differently; a clock
// offset does neither, so only a lag equal on every leg and a pure delay
// is taken for one.
struct ClockOffsetCheck {
  bool tested = false;        // no encoder columns, servo_lag selected, the clock not drifting
  double offset_s = 0.0;      // δ that would do instead of the lag, beside the other selected effects
  double sigma_s = 0.0;       // its 1-σ (grown for the residual's autocorrelation)
  bool replaces_lag = false;  // servo_lag no longer earns its place beside δ
};

// How the final Ceres fit went.
struct RobustFitSummary {
  double huber_m = 0.0;
  int iterations = 0;
  bool converged = false, covariance_ok = false;
};

// What a calibration applies (calibration_set.h): the effects that best
// predict held-out error, whether or not the diagnosis can name each, and
// their parameters fitted together on every run (the robust fit, as the
// selected effects').
struct CalibrationResult {
  std::vector<Effect> effects;
  std::vector<Eigen::VectorXd> theta, sigma;  // one per effect, in that order (sigma: 1-σ)
  ChosenBy chosen_by = ChosenBy::kIdentified;
  double heldout_rms_m = 0.0;             // point A, √(3·held-out MSE per coordinate)
  double identified_heldout_rms_m = 0.0;  //   of the identified effects alone
};

struct Diagnosis {
  DesignOptions design;  // the bases' settings the result holds for
  int samples = 0;
  std::int64_t timing_excluded = 0;  // samples the data flagged timing_event, left out
  std::vector<std::string> runs;
  ChangeSearch changes;               // the rig's changes within the session, found before anything else
  GapSummary gap;                     // before any effect (frame estimated)
  std::vector<EffectResult> effects;  // ranked: selected first, then rejected by gain
  std::vector<Effect> selected;
  CalibrationResult calibration;  // what a calibration applies
  Conclusion conclusion = Conclusion::kNone;
  std::vector<std::string> holdout_runs;
  RmsMax holdout_before, holdout_after;
  double shrink = 0.0;
  double gap_shrink = 0.0;         // of the gap above the noise floor (gap_shrink.h)
  double noise_floor_rms_m = 0.0;  // point-A noise the tracker alone explains
  // The effects' prior's measurement variance per coordinate (m²; linear_fit.h's
  // PriorWeights): the larger of the floor's and the frame-only fit's. The
  // searches over the bases' non-linear parameters use the same.
  double prior_sigma2 = 0.0;
  RmsMax unexplained;             // in-sample, after the selected effects
  Whiteness whiteness;            // of the in-sample residual
  ResidualStructure structure;    // of the held-out residual: decides unknown, as do
  BaseTiltCheck base_tilt;        //   a base tilting under the payload,
  ClockDriftCheck clock_drift;    //   a tracker clock drifting,
  ClockOffsetCheck clock_offset;  //   a lag that may be the clock's, and a lag the encoders miss
  std::string unexplained_note;
  std::vector<SampleGap> series;
  TimeOffset time_offset;            // the tracker's clock, a nuisance (time_offset.h)
  std::optional<PrMode> applied_pr;  // the compensation found in the data (nullopt: another)
  double applied_pr_ratio = 0.0;
  // With encoders: the drives' following error at A, the part servo_lag's
  // terms describe and the rest, and whether the rest was taken out of the
  // residual (design.h).
  bool has_encoder = false;
  double drives_described_rms_m = 0.0, drives_rest_rms_m = 0.0;
  bool drives_rest_taken_out = false;
  RobustFitSummary robust;
  double condition_number = 0.0;  // of the selected model's column-scaled Jacobian
  std::string platform;           // calibration::PlatformFingerprint of the model it ran on
  Eigen::VectorXd frame;          // δt, δω around (R0, t0), with the selected effects
  Matrix3 R0 = Matrix3::Identity();
  Vector3 t0 = Vector3::Zero();
  double seconds = 0.0;
  Against against = Against::kNominal;
  double recorded_correction_rms_m = 0.0;  // what the recorded calibration moved A by (RMS); 0: none
};

Diagnosis Diagnose(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options = {});

}  // namespace edsp::gap
