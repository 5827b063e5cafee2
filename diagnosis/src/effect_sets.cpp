#include "edsp/diagnosis/effect_sets.h"

#include <cmath>

namespace edsp::gap {

std::vector<Effect> With(std::vector<Effect> set, Effect e) {
  set.push_back(e);
  return set;
}

std::vector<Effect> Without(const std::vector<Effect>& set, Effect e) {
  std::vector<Effect> rest;
  for (Effect x : set) {
    if (x != e) rest.push_back(x);
  }
  return rest;
}

std::vector<double> LogGains(const std::vector<double>& with_sse, const std::vector<double>& without_sse) {
  std::vector<double> gain;
  for (std::size_t k = 0; k < with_sse.size(); ++k) {
    gain.push_back(std::log(std::max(without_sse[k], 1e-300) / std::max(with_sse[k], 1e-300)));
  }
  return gain;
}

bool EarnsItsPlace(Evaluator& eval, double cv, const std::vector<Effect>& selected, Effect e,
                   const DiagnoseOptions& o) {
  const std::vector<Effect> rest = Without(selected, e);
  const double base = eval.Cv(rest);
  const bool gains = base > 0.0 && (base - cv) / base >= o.min_cv_gain;
  return gains && eval.SignificantlyBetter(selected, rest, o.significance);
}

std::vector<Effect> RedundantBeside(Evaluator& with_structure, double cv, const std::vector<Effect>& selected,
                                    const DiagnoseOptions& o, std::optional<Effect> own) {
  std::vector<Effect> explained;
  for (Effect e : selected) {
    if (e != own && !EarnsItsPlace(with_structure, cv, selected, e, o)) explained.push_back(e);
  }
  return explained;
}

}  // namespace edsp::gap
