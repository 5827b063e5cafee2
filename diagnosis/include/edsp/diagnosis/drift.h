#pragma once
// edsp-gap drift: what changed on a rig since a calibration. A rig lives:
// screws wear (backlash grows), a joint is re-seated (a leg offset jumps),
// the hall warms. Given the calibration in force (the baseline, a saved
// model) and a new session's measurement, each of the baseline's applied
// parameters is fitted again, its change sized with both fits'
// uncertainties, effects that appeared or vanished are named, and the
// held-out error the baseline leaves decides whether to recalibrate.
//
// The data may be recorded with the baseline applied by the kinematics (the
// usual case: the residual against the nominal model is then what the
// baseline no longer explains) or without it (the baseline is then applied
// offline first). Either way the new fit estimates the change δ from the
// baseline with the diagnosis's ridge towards "no change", and
//   after = before + δ,   σ(change) = √(σ_δ² + σ_before²),
// σ_δ the larger of the formal σ and the jackknife's over the session's
// runs (linear_fit.h), as σ_before is in the saved model: what the model
// leaves out of a whole rig moves a parameter with the motion, which the
// formal σ cannot see.
// A change counts when |change| ≥ z·σ, z the larger of 3 and the
// Bonferroni bound of a 5% chance that anything of an unchanged rig passes
// it (so many parameters do not make noise a change), and when it
// moves point A on the session by a quarter of the tracker's noise floor:
// a whole rig's parameters differ between motion sets by more than their
// σ (a periodic error's phase seen at other screw angles, a lag on other
// speeds) without anything on the rig having changed.
// The 5% is shared evenly by the drift's two questions: which of the six
// legs' lengths changed, and which of the many parameters did. A leg's
// jump is the commonest change of a rig (a joint re-seated, a coupling
// slipped); tested among some eighty parameters it would need z ≈ 3.4 for
// each leg, more the more effects the model holds, where its own family
// of six needs 3. The 5% is nominal: it holds for σ that are exact, and a
// whole rig's model is not the rig (docs/calibration.md gives the rates
// measured). Whether an effect vanished is judged apart, against one bar
// over the legs and the applied parameters at the whole 5%.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "edsp/diagnosis/diagnose.h"

namespace edsp::gap {

inline constexpr double kChangeAtAShare = 0.25;
// The chance that an unchanged rig reports any change, and each question's share.
inline constexpr double kFamilyWiseChance = 0.05;
inline constexpr double kLegsShare = 0.5;

struct DriftOptions {
  bool recorded_with_baseline = true;  // the data's commands carried the baseline's correction
  bool apply_ambiguous = false;        // the baseline as the kinematics applied it (--apply-ambiguous)
  double threshold_m = 0.0;            // recalibrate above this held-out RMS; 0: 1.5× the data's noise floor
  DiagnoseOptions diagnose;            // for the effects that appeared
};

struct ParameterChange {
  Effect effect = Effect::kLegOffset;
  std::string parameter;  // its key in the model's JSON (e.g. "backlash_m"), "theta" for a polar pair's θ
  int index = 0;          // the value's index in that group (per leg: leg − 1, or 3·(leg − 1) + axis)
  int leg = 0;            // 1–6 for a per-leg value, 0 otherwise
  double before = 0.0, after = 0.0, change = 0.0, sigma = 0.0;  // SI
  double z = 0.0;                                               // change / sigma
  double at_a_m = 0.0;  // how far the change moves point A on this session: RMS of its column × change
  int theta_index = 0;  // of the effect's θ
  bool applied = true;  // the kinematics applies it (calibration::UnappliedParameters): only such can count as changed
};

// A leg's constant length, changed (a joint re-seated, a coupling slipped),
// asked of every leg whatever the baseline holds of the legs' geometry: the
// six offsets fitted from zero beside the frame and the parameters found
// changed, every other parameter (the joint centres among them) held at the
// baseline's. Beside the joint centres' 36 changes a leg's length is not
// known to within 100 µm on a session's motions (they and the frame mimic it
// over a small workspace); held, it is known to a few µm. σ is the larger of
// the formal one (grown for a residual that is not white) and the
// jackknife's over the session's runs, times √2: the baseline's own error in
// that length (its joint centres' errors seen on motions the fit did not
// run), which the model does not save, taken as large as the session's.
// The effects that set a leg's constant length (leg offsets, joint centres).
bool IsLegGeometry(Effect effect);

struct LegChange {
  int leg = 0;  // 1–6
  double change_m = 0.0, sigma_m = 0.0, z = 0.0;
  double at_a_m = 0.0;  // how far it moves point A on this session (RMS)
};

struct DriftReport {
  bool recorded_with_baseline = true;
  int samples = 0;
  std::vector<ParameterChange> parameters;  // every parameter the baseline applies
  std::vector<ParameterChange> changed;     // those the kinematics applies with |z| ≥ z_threshold
                                            // that move A by kChangeAtAShare of the noise floor
  std::vector<LegChange> legs;              // every leg's length
  std::vector<LegChange> legs_changed;      // those past leg_z_threshold and the A bar
  double z_threshold = 3.0;                 // the parameters'
  double leg_z_threshold = 3.0;             // the legs' lengths'
  std::vector<Effect> appeared;             // identified now, not in the baseline
  std::vector<Effect> vanished;             // in the baseline, now within z·σ of zero (drift.h's header)
  double heldout_rms_m = 0.0;               // what the baseline leaves on this data (frame refitted)
  double heldout_max_m = 0.0;
  double noise_floor_rms_m = 0.0;
  double threshold_m = 0.0;
  bool recalibrate = false;
};

// Throws MeasurementError naming what is wrong with the baseline.
DriftReport Drift(const PlatformModel& model, const nlohmann::json& baseline, const std::string& origin,
                  const MeasurementData& data, const DriftOptions& options = {});

// z such that N normal tests all stay within ±z with probability 1 − chance
// (two-sided Bonferroni), and at least 3.
double ChangeThreshold(int tests, double chance = kFamilyWiseChance);

nlohmann::json ToJson(const DriftReport& report);
// One change: "backlash play leg 3: 22.0 → 37.0 µm, +15.0 ± 2.0 µm (7.5σ)".
std::string ChangeText(const ParameterChange& change);
// "leg 4 length: +40.2 ± 3.1 µm (13.0σ)".
std::string LegChangeText(const LegChange& change);
// Each leg whose length changed, each parameter that changed, then what
// appeared, vanished, and the verdict.
std::string DriftText(const DriftReport& report);

}  // namespace edsp::gap
