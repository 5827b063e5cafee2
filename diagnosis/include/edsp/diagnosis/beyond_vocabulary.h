#pragma once
// What lies outside the effect vocabulary, and what it takes from the
// selected effects. The first four checks put a signature no effect has
// beside the selected effects as a nuisance (structure_nuisance.h,
// time_offset.h):
//   - a mode at the residual's structure (a sway, a stand ringing);
//   - a base tilting under the payload's moment;
//   - a tracker clock drifting from the controller's;
//   - without encoders, a tracker clock offset instead of a servo lag;
// the last reads the encoders' share of a fitted servo lag
// (encoder_check.h): with encoders, a lag the drives' own error does not
// show. One that predicts the held-out runs better names `unknown` in the
// conclusion and what is left (`unexplained_note`); each selected effect
// that no longer earns its place beside it is `ambiguous` with `unknown`
// (no calibration applies it by default). docs/diagnosis.md, steps 8-12.

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/effect_sets.h"

namespace edsp::gap {

// Runs every check on `out`, whose selected effects, verdicts, structure
// and conclusion the diagnosis has set; `plain` scores effect sets on `d`
// with the effects' prior `prior`.
void CheckBeyondTheVocabulary(const Design& d, const Eigen::VectorXd& prior, Evaluator& plain, const DiagnoseOptions& o,
                              Diagnosis* out);

}  // namespace edsp::gap
