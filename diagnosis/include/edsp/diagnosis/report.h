#pragma once
// What edsp-gap prints and saves: the JSON report of interfaces.md §4 (and
// more), the saved model a later `evaluate` applies to new data, and the
// readable report directory.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/percent_text.h"  // Percent, which the ranking tables use

namespace edsp::gap {

nlohmann::json ToJson(const Diagnosis& diagnosis);

// An entry of the report's ranking (ToJson's "effects", interfaces.md §4):
// an effect's result, or one of the vocabulary's pseudo-effects, `none`
// (nothing beyond the noise) and `unknown` (what no effect explains).
struct RankedEntry {
  enum class Kind { kEffect, kNone, kUnknown };
  Kind kind = Kind::kEffect;
  const EffectResult* result = nullptr;  // kEffect: the effect's, in the diagnosis
};

// The ranking, as the report lists it and the benchmark scores it: `none`
// first when the diagnosis concludes that; the effects in rank order, and
// `unknown` after the selected ones (first when none is) when the
// conclusion names it. The entries point into `diagnosis`.
std::vector<RankedEntry> Ranking(const Diagnosis& diagnosis);
// The effect's name, or the pseudo-effect's ("none", "unknown").
std::string RankedName(const RankedEntry& entry);
// The effect's verdict; a pseudo-effect is the conclusion itself: identified.
Verdict RankedVerdict(const RankedEntry& entry);

// The tracker's clock in one sentence: its offset (time_offset.h), whether
// without encoders an offset does as well as the servo_lag found, and how
// fast it drifts over the session (the clock checks).
std::string TrackerClockNote(const Diagnosis& diagnosis);

// The rig's changes within the session (change_point.h) in one sentence:
// each event, or that one rig explains the session, and the steps a drift
// explained as well.
std::string ChangesText(const Diagnosis& diagnosis);

// What a calibration recorded with the data did at point A and what the
// diagnosis read it against, in one sentence ("" when the data carried none).
std::string RecordedCorrectionText(const Diagnosis& diagnosis);

// The selected effects with their parameters: what `evaluate` applies.
nlohmann::json ModelJson(const Diagnosis& diagnosis);

// A model of no effect: `Evaluate` with it aligns the data and measures.
nlohmann::json EmptyModelJson();

// The part of a saved model the kinematics applies: its `identified`
// effects (and those saved without a verdict), the `ambiguous` ones only
// when asked, as kinematics/calibration.h reads it. A prediction to set
// beside a measurement with the calibration applied must use this.
nlohmann::json AppliedModelJson(const nlohmann::json& saved, bool apply_ambiguous);

// One run (motion) of the evaluated data.
struct RunEvaluation {
  std::string run;
  RmsMax before, after;
};

struct Evaluation {
  RmsMax before, after;  // frame re-estimated on the data in both
  double shrink = 0.0;
  double gap_shrink = 0.0;  // of the gap above the noise floor (gap_shrink.h)
  int samples = 0;
  std::int64_t timing_excluded = 0;    // samples the data flagged timing_event, left out
  double timing_excluded_share = 0.0;  //   of all its samples (before any decimation)
  std::int64_t timing_kept = 0;        // flagged, kept on request
  double timing_kept_share = 0.0;
  std::vector<RunEvaluation> by_run;  // the same, per run (one frame for all)
  double noise_floor_rms_m = 0.0;     // the tracker's noise at A, from the data (NoiseFloorRms)
  TimeOffset time_offset;             // the data's tracker clock, removed as the frame is
  // The data carried a calibration's correction and the model takes its
  // place: both figures are against the nominal model (recorded_correction.h).
  bool against_nominal = false;
};

// Applies a saved model (ModelJson) to data it has never seen: the tracker
// frame is re-estimated (it is a nuisance), the effects' parameters are not.
// On data recorded with a calibration in force the model replaces it: the
// data is read against the nominal model, `before` then the rig's whole gap.
// Throws MeasurementError naming what is wrong with the model.
Evaluation Evaluate(const PlatformModel& model, const MeasurementData& data, const nlohmann::json& saved,
                    const std::string& origin);

nlohmann::json ToJson(const Evaluation& evaluation);

// report.md for people: the verdict first (ranking, held-out shrink), the
// found effects' parameters in engineering units, where the gap lies, then
// what to do next. The PNGs it names are written by WriteReport.
std::string ReportMarkdown(const Diagnosis& diagnosis);

// Markdown report with PNG plots (gnuplot) in `dir`; returns the files written.
std::vector<std::string> WriteReport(const Diagnosis& diagnosis, const std::string& dir);

}  // namespace edsp::gap
