#include "edsp/diagnosis/calibration_set.h"

#include <algorithm>
#include <limits>

namespace edsp::gap {

namespace {

std::vector<Effect> Allowed(std::vector<Effect> set, const std::vector<Effect>& excluded) {
  set.erase(std::remove_if(set.begin(), set.end(), [&](Effect e) { return Contains(excluded, e); }), set.end());
  return set;
}

std::vector<Effect> Forward(Evaluator& eval, std::vector<Effect> set, const std::vector<Effect>& excluded) {
  double cv = eval.Cv(set);
  for (;;) {
    Effect best = Effect::kLegOffset;
    double best_cv = std::numeric_limits<double>::infinity();
    for (Effect e : AllEffects()) {
      if (Contains(set, e) || Contains(excluded, e)) continue;
      const double c = eval.Cv(With(set, e));
      if (c < best_cv) best_cv = c, best = e;
    }
    if (!(best_cv < cv * (1.0 - kCalibrationMinGain))) return set;
    set.push_back(best);
    cv = best_cv;
  }
}

std::vector<Effect> Backward(Evaluator& eval, const std::vector<Effect>& excluded) {
  std::vector<Effect> set = Allowed(AllEffects(), excluded);
  double cv = eval.Cv(set);
  while (!set.empty()) {
    Effect drop = set.front();
    double best_cv = std::numeric_limits<double>::infinity();
    for (Effect e : set) {
      const double c = eval.Cv(Without(set, e));
      if (c < best_cv) best_cv = c, drop = e;
    }
    // Out unless the held-out error misses it by kCalibrationMinGain.
    if (!(best_cv < cv * (1.0 + kCalibrationMinGain))) return set;
    set = Without(set, drop);
    cv = std::min(cv, best_cv);
  }
  return set;
}

}  // namespace

CalibrationSet ChooseCalibrationSet(Evaluator& eval, const std::vector<Effect>& identified,
                                    const std::vector<Effect>& selected, const std::vector<Effect>& excluded) {
  CalibrationSet best;
  best.effects = Allowed(identified, excluded);
  best.chosen_by = ChosenBy::kIdentified;
  best.cv_mse = best.identified_cv_mse = eval.Cv(best.effects);
  const std::vector<Effect> named = Allowed(selected, excluded);
  const std::pair<ChosenBy, std::vector<Effect>> candidates[] = {{ChosenBy::kSelected, named},
                                                                 {ChosenBy::kForward, Forward(eval, named, excluded)},
                                                                 {ChosenBy::kBackward, Backward(eval, excluded)}};
  for (const auto& [how, set] : candidates) {
    const double cv = eval.Cv(set);
    if (cv < best.cv_mse * (1.0 - kCalibrationMinGain)) best.effects = set, best.chosen_by = how, best.cv_mse = cv;
  }
  return best;
}

}  // namespace edsp::gap
