#pragma once
// What a calibration applies: the best predictor of held-out error, which
// need not be the set of effects the diagnosis can name. Effects the data
// cannot tell apart (ambiguous), or that none of which beats the model
// without it run by run on its own, can still predict the held-out runs
// better together; a controller wants the prediction, the report wants
// the names. Four candidates, scored on the same held-out folds as
// selection (diagnose.h):
//   - the identified effects (what the diagnosis names for sure);
//   - the selected effects (those and the ones it finds ambiguous);
//   - those, then greedily whatever effect cuts the held-out MSE most while
//     it cuts it by kCalibrationMinGain, no run-by-run test and no
//     ambiguity rule (a predictor needs neither);
//   - the whole vocabulary, then greedily without whatever effect the
//     held-out MSE does not miss (backward elimination), for effects that
//     only help together.
// The lowest held-out MSE wins; a richer set must beat a simpler one by
// kCalibrationMinGain, so the names are applied unless more predicts better.

#include <vector>

#include "edsp/diagnosis/chosen_by.h"
#include "edsp/diagnosis/effect_sets.h"

namespace edsp::gap {

inline constexpr double kCalibrationMinGain = 0.01;

struct CalibrationSet {
  std::vector<Effect> effects;  // in the order they were added
  ChosenBy chosen_by = ChosenBy::kIdentified;
  double cv_mse = 0.0;             // held-out MSE per coordinate, m²
  double identified_cv_mse = 0.0;  //   of the identified effects alone
};

// `excluded`: effects no candidate may hold (one whose fit beside the
// others is not a real platform's, calibration::ParameterLimit).
CalibrationSet ChooseCalibrationSet(Evaluator& eval, const std::vector<Effect>& identified,
                                    const std::vector<Effect>& selected, const std::vector<Effect>& excluded = {});

}  // namespace edsp::gap
