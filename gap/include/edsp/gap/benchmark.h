#pragma once
// edsp-gap benchmark: scenarios of random effect combinations drawn on a
// virtual rig, the truth hidden from the diagnosis, which sees only the
// measurement CSV and the nominal config; then scored: is the top-ranked
// effect a true one, are both of a pair found, is nothing identified on
// effect-free data, is an effect outside the vocabulary `unknown`, how far
// the held-out gap shrinks. Two generators: edsp's own rig (edsp-sim rig's
// offline run) and the blind rig (blindrig/, written apart from edsp's rig,
// model and diagnosis, with effects outside the vocabulary).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "edsp/diagnosis/conclusion.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/gap/generator.h"
#include "edsp/gap/rig_scenarios.h"
#include "edsp/gap/scenario_kind.h"

namespace edsp::gap {

struct BenchmarkOptions {
  int scenarios = 20;
  std::uint64_t seed = 1;
  std::string config_path;        // nominal model; default: the paper's platform
  double tracker_noise_m = 5e-6;  // 1-σ per axis
  double tracker_rate_hz = 100.0;
  // The paper's four and four mixed motions (every axis at once): each run
  // held out is then predicted from runs that span the same workspace.
  std::vector<std::string> motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2", "M3", "M4"};
  Generator generator = Generator::kRig;  // the noise and rate above are the rig's (the blind rig draws its own)
  // Blind generator: the checks that need the encoders' absence (the
  // clock's offset, step 12) run on every draw without them; the rest of
  // each draw is the same.
  EncoderColumns encoders = EncoderColumns::kDrawn;
  // The closed loop (rig generator only): after the diagnosis, these motions,
  // which no fit saw, run without and with the saved model applied by the
  // kinematics; empty: not run.
  std::vector<std::string> closed_loop_motions = {"Ly", "Rx", "M9"};
  // Every scenario a whole rig of every class (edsp's DrawEveryClassRig,
  // the blind rig's DrawBlindEveryClassRig) instead of the mix of kinds.
  bool whole_rigs = false;
  std::string keep_dir;  // empty: scenarios in a temporary directory, removed
  bool progress = true;  // a progress bar on stderr
};

// Scored, whichever generator drew it.
struct ScenarioScore {
  int index = 0;
  ScenarioKind kind = ScenarioKind::kNone;
  std::vector<std::string> truth;  // effect names; out of vocabulary: its own name
  std::string description;
  std::vector<std::string> found;       // identified or ambiguous, ranked
  std::vector<std::string> identified;  // identified, ranked (a whole rig's: leg offsets by joint centres)
  std::string top;                      // first ranked entry ("none"/"unknown" included)
  Conclusion conclusion = Conclusion::kNone;
  bool top_true = false, all_found = false, false_identified = false;
  bool top_identified_true = false;  // the first `identified` effect is a true one
  bool all_identified = false;       // every true effect `identified` (a whole rig's leg offsets: or its
                                     // joint centres, whose fit moves each leg's length too)
  // A whole rig's true effects not identified, split by whether these runs
  // can show them at all: the true effects without it predict the held-out
  // runs worse by selection's min_cv_gain (shown), or not (a light payload's
  // compliance of a few µm, under the tracker's noise: below what the runs
  // show). Every shown effect identified: all_shown_identified.
  std::vector<std::string> missed_shown, missed_unshown;
  bool all_shown_identified = false;
  double before_rms_m = 0.0, after_rms_m = 0.0, shrink = 0.0, noise_floor_m = 0.0;
  double noise_sigma_m = 0.0;  // the generator's tracker noise, 1-σ per axis (the truth, not estimated)
  double gap_shrink = 0.0;     // GapShrink against that noise
  double simulate_s = 0.0, diagnose_s = 0.0;
  // A miss (a true effect not identified first or at all, or a false one
  // identified): the held-out RMS the true effects reach beside the one the
  // selected effects reach, both fitted the same way (heldout_score.h). The
  // data tell them apart when the truth's held-out MSE is lower by at least
  // selection's min_cv_gain (diagnose.h); otherwise the miss is one no
  // selection on these runs could avoid.
  bool miss = false;
  double truth_heldout_rms_m = 0.0, found_heldout_rms_m = 0.0;
  bool data_tell_apart = false;
  // Measured on the rig with the calibration applied (closed_loop_motions),
  // beside the model's own prediction from the uncalibrated run.
  bool closed_loop = false;
  double closed_before_rms_m = 0.0, closed_after_rms_m = 0.0, closed_predicted_rms_m = 0.0;
  double closed_shrink = 0.0, closed_predicted_shrink = 0.0;
  double closed_gap_shrink = 0.0, closed_predicted_gap_shrink = 0.0;  // GapShrink, the same tracker's noise
  double closed_loop_s = 0.0;
};

struct BenchmarkResult {
  BenchmarkOptions options;
  std::vector<ScenarioScore> scores;
  int single = 0, single_top_true = 0;
  int pairs = 0, pairs_both = 0;
  int single_identified_top_true = 0;
  int pairs_both_identified = 0;
  int clean = 0, clean_nothing_identified = 0, clean_none = 0;
  int out_of_vocabulary = 0, out_of_vocabulary_unknown = 0;  // conclusion unknown, nothing identified
  // Whole rigs: every effect the runs show identified; the held-out RMS within
  // kWholeRigClosedFloorRatio × the tracker's noise floor (√3·σ); a false
  // effect identified.
  int whole = 0, whole_all_named = 0, whole_closed = 0, whole_wrong = 0;
  int whole_all_identified = 0;  // every true effect, shown or not
  int whole_unshown = 0;         // true effects these runs cannot show, over all whole rigs
  double median_whole_after_over_floor = 0.0;
  int any_false_identified = 0;  // scenarios of any kind with an effect identified that is not there
  int extra_identified = 0;      // scenarios with effects where a false one was also identified
  double median_shrink = 0.0;    // scenarios with effects of the vocabulary
  // What a perfect model would reach on them: the held-out gap down to the
  // tracker's noise floor, 1 − floor/before. The median shrink can exceed
  // it only by the floor estimate's error (a few per cent of the floor)
  // however good the diagnosis: draws near the floor bound it.
  double median_attainable_shrink = 0.0;
  // The shrink target is read on the gap, the departure beyond the
  // tracker's noise (GapShrink), over the same scenarios.
  double median_gap_shrink = 0.0;
  int misses = 0, misses_told_apart = 0;  // in-vocabulary and effect-free scenarios (ScenarioScore::miss)
  double median_after_over_noise = 0.0;
  double median_diagnose_s = 0.0;
  // Scenarios with effects of the vocabulary, run in closed loop.
  int closed_loop = 0;
  double median_closed_shrink = 0.0, median_closed_predicted_shrink = 0.0;
  double median_closed_gap_shrink = 0.0, median_closed_predicted_gap_shrink = 0.0;
  std::vector<int> closed_disagree;      // measured and predicted shrink 10 points or more apart
  std::vector<int> closed_gap_disagree;  //   the same of the gap above the noise
};

inline constexpr double kWholeRigClosedFloorRatio = 1.5;

BenchmarkResult RunBenchmark(const BenchmarkOptions& options);

nlohmann::json ToJson(const BenchmarkResult& result);
void PrintBenchmark(const BenchmarkResult& result);

}  // namespace edsp::gap
