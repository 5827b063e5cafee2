#pragma once
// Whether one rig explains the whole session, asked before any effect is
// fitted: a rig that changed during it (a coupling slipping, a joint bolt
// settling, the tracker's stand knocked) is one rig before the change and
// another after, and no effect of the vocabulary, which holds for the whole
// session, explains it.
//
// The search looks for a step in time in each signature a change can have:
// one leg's length (6 signatures, the leg_offset column of that leg) and the
// tracker's frame (its 6 columns). Beside the frame and every effect of the
// vocabulary (with the diagnosis's prior), a step at each candidate instant
// is scored by the squared error it removes, exactly (every column
// projected out) from running sums in one pass over the samples in time.
// The best instant of each signature is then judged by
//   - its size against the noise the residual after it shows: white
//     noise's σ², widened by how much more the residual adds up along the
//     signature over blocks of the session (block_s long, cut at runs) than
//     sample by sample (a misfit correlated over seconds), one figure per
//     signature for the whole session; the statistic must pass χ² of the
//     step's columns at `false_alarm` shared over every candidate instant
//     of the grid and every signature (Bonferroni), and
//   - what is left along the signature after the step, fitted block by
//     block: past white noise's χ² (1%), the signature holds structure (a
//     sway the model lacks, runs that sit apart), not one change, unless
//     the step's statistic is step_over_structure times what is left (a
//     change standing on a misfit the model lacks: a soft drive loop seen
//     without encoders), and
//   - a drift of the same signature (linear in time, or saturating with
//     each of the thermal time constants): the step is an event only where
//     it removes clearly more than the best drift (step_over_drift, in the
//     same widened σ²).
// Of the steps that are events, the one furthest past its bar is taken,
// unless another within shadow_s of it explains the data better counting
// its columns (BIC); then the search runs again.
// A step that fails either of the last two is named as rejected, with the
// alternative that won and its evidence, and is not an event; so is a step
// whose size is unknown to a millimetre or a milliradian in some direction,
// and a step within shadow_s of a better one (further past its bar) of
// another signature that was turned away: the same change seen through
// a signature that mimics part of it.
// An event found is removed from the data (the rows before it moved to the
// rig after it), and the search runs again for the next, up to max_events.
// The diagnosis then works on the corrected data: the rig as it is at the
// session's end, the one a calibration applies. docs/diagnosis.md, step 0.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/measurement_data.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::gap {

enum class ChangeKind { kLegLength, kTrackerFrame };

// "leg_length" | "tracker_frame": the report's and the JSON's names.
const char* ChangeKindName(ChangeKind kind);

struct ChangePointOptions {
  bool search = true;
  double false_alarm = 0.01;    // chance of an event on a rig that did not change, over the whole search
  double block_s = 10.0;        // the blocks the noise's correlation is read over (cut at runs too)
  double grid_s = 0.1;          // the scan's candidate instants, then every sample around the best
  double step_over_drift = 10;  // the step's advantage over the best drift, in σ² (as the BIC's margin)
  // A step's statistic against what is left along its signature block by
  // block, for it to stand as one change beside structure (a step fitted
  // into a sway, a ramp or runs that sit apart stands far lower).
  double step_over_structure = 10;
  // Steps of two signatures this close in time are one change seen twice:
  // the shadow of a better one turned away is no event, and of two accepted
  // the better explanation is taken.
  double shadow_s = 1.0;
  int max_events = 4;
  double min_side_share = 0.01;  // of the samples, on each side of an instant (and at least 30)
  // The drifts a step must beat: linear in time and saturating, 1 − e^(−t/τ).
  std::vector<double> drift_time_constants_s = {150.0, 300.0, 600.0, 1200.0, 2400.0, 4800.0};
};

// Why a significant step is no event: a drift of the same signature
// explains it as well; its signature varies block by block beyond it
// (structure rather than one change); the session cannot size it (its σ
// past 1 mm or 1 mrad in some direction); or a better step of another
// signature at its instant was turned away (its shadow).
enum class StepRejection { kNone, kDrift, kStructure, kUndetermined, kOtherSignature };
// "drift", "structure", "undetermined", "other_signature" ("" for none): the report's words.
const char* StepRejectionName(StepRejection why);

struct ChangeEvent {
  ChangeKind kind = ChangeKind::kLegLength;
  int leg = -1;          // 0-based (kLegLength)
  double time_s = 0.0;   // the first sample of the rig after the change
  double after_s = 0.0;  //   the last sample of the rig before it: the change lies between
  std::string run;       // of the first sample after
  // leg: 1 value, its length after − before (m); tracker: its frame after −
  // before, δt (m, 3) then δω (rad, 3), as the design's frame columns.
  Eigen::VectorXd size, sigma;
  double wald = 0.0, threshold = 0.0;                // the step's statistic and the bar it passed
  double inflation = 1.0;                            // the noise's variance along the signature over white noise's
  double step_sigma2 = 0.0;                          // squared error the step removes, in the widened σ²
  double drift_sigma2 = 0.0;                         //   and the best drift of the same signature
  std::string drift;                                 //   that drift: "linear" or "tau_600s"
  double left_sigma2 = 0.0;                          // what the signature holds block by block after the step, in σ²
  double left_threshold = 0.0;                       //   and its χ² bar (1%): past it, structure, not one change
  StepRejection alternative = StepRejection::kNone;  // rejected: what won instead of one change
};

struct ChangeSearch {
  bool searched = false;
  std::vector<ChangeEvent> events;    // in the order found (largest first)
  std::vector<ChangeEvent> rejected;  // significant steps a drift explained as well: not events
  int blocks = 0, candidates = 0;     // blocks of the noise's reading; instants the scan tried
  double seconds = 0.0;
  double structural_mode_hz = 0.0;  // the sway searched beside the steps (0: none; diagnose.cpp)
};

// One sentence for an event, as the report and the text give it: "at
// 123.40 s (run Lx), leg 4 became 80.1 µm ± 0.9 longer".
std::string DescribeEvent(const ChangeEvent& event);

// Searches `data` (rows already thinned as the diagnosis thins them); with
// events found, `corrected` is `data` with every row before each event
// moved to the rig after it (else a copy of `data`).
ChangeSearch FindChanges(const PlatformModel& model, const MeasurementData& data, const DesignOptions& design,
                         const ChangePointOptions& options, MeasurementData* corrected);

}  // namespace edsp::gap
