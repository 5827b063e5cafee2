#pragma once
// Effect sets scored on held-out runs: the vocabulary's arithmetic that
// selection and the checks beyond the vocabulary share (diagnose.cpp,
// beyond_vocabulary.cpp). Internal to edsp-gap.
//   - With, Without, Contains: effect sets;
//   - LogGains: each held-out fold's log ratio, for the paired test;
//   - Tied: two non-nested explanations the data do not tell apart;
//   - Evaluator: a set's held-out error on a design, memoised;
//   - WithStructure: a design with a nuisance beside the frame;
//   - RedundantBeside: the selected effects a nuisance makes redundant.

#include <algorithm>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/paired_test.h"
#include "edsp/diagnosis/structure_nuisance.h"

namespace edsp::gap {

std::vector<Effect> With(std::vector<Effect> set, Effect e);
std::vector<Effect> Without(const std::vector<Effect>& set, Effect e);

template <typename T>
bool Contains(const std::vector<T>& set, const T& e) {
  return std::find(set.begin(), set.end(), e) != set.end();
}

// Each fold's log ratio of its held-out squared error without and with.
std::vector<double> LogGains(const std::vector<double>& with_sse, const std::vector<double>& without_sse);

// Two non-nested explanations of one signature tied (diagnose.cpp's
// Verdicts; a base tilt in place of the effects it resembles): the
// challenger takes up ambiguity_ratio of the incumbent's held-out gain (and
// min_cv_gain), and the incumbent does not beat it run by run (the paired
// test). Gains are fractions of the held-out MSE both are added to;
// `incumbent_over_challenger()` gives the folds' log ratios (LogGains), and
// is asked for only when the gains tie, since it fits every fold.
template <typename LogGainsOf>
bool Tied(double challenger_gain, double incumbent_gain, LogGainsOf incumbent_over_challenger,
          const DiagnoseOptions& o) {
  return challenger_gain >= std::max(o.min_cv_gain, o.ambiguity_ratio * incumbent_gain) &&
         !PairedGainIsSignificant(incumbent_over_challenger(), o.significance);
}

// Held-out and in-sample errors of effect sets, memoised (selection asks
// for the same set again when it checks alternatives).
class Evaluator {
 public:
  Evaluator(const Design& d, const GramSet& gram, Eigen::VectorXd prior)
      : d_(d), gram_(gram), prior_(std::move(prior)) {}

  // Mean squared held-out residual (per coordinate), leave-one-fold-out.
  double Cv(const std::vector<Effect>& set) {
    const std::vector<double>& sse = FoldSse(set);
    return std::accumulate(sse.begin(), sse.end(), 0.0) / gram_.Residuals(gram_.AllFolds());
  }

  // Each fold's held-out sum of squared residuals, fitted on the others.
  const std::vector<double>& FoldSse(const std::vector<Effect>& set) {
    const std::string key = Key(set);
    const auto it = fold_sse_.find(key);
    if (it != fold_sse_.end()) return it->second;
    const Columns cols = ColumnsOf(d_, set);
    std::vector<double> sse;
    for (int f = 0; f < gram_.folds(); ++f) {
      sse.push_back(gram_.Sse(cols, gram_.Solve(cols, gram_.AllBut(f), prior_), {f}));
    }
    return fold_sse_[key] = std::move(sse);
  }

  // Whether `with` predicts the held-out runs better than `without` run by
  // run, not only pooled: a one-sided paired t-test at level `alpha` of the
  // log ratio of each fold's held-out squared error, so that a gain one run
  // carries (a structure that happens to resemble the effect there) is not
  // taken for the effect. Ratios, not differences: runs of very different
  // size (a rotation beside a lift) would otherwise drown the test in
  // their scale.
  bool SignificantlyBetter(const std::vector<Effect>& with, const std::vector<Effect>& without, double alpha) {
    return PairedGainIsSignificant(LogGains(FoldSse(with), FoldSse(without)), alpha);
  }

  // In-sample sum of squared residuals, every fold fitted.
  double Rss(const std::vector<Effect>& set) {
    const Columns cols = ColumnsOf(d_, set);
    const std::vector<int> all = gram_.AllFolds();
    return gram_.Sse(cols, gram_.Solve(cols, all, prior_), all);
  }

 private:
  static std::string Key(std::vector<Effect> set) {
    std::sort(set.begin(), set.end());
    std::string key;
    for (Effect e : set) key += EffectName(e), key += ',';
    return key;
  }
  const Design& d_;
  const GramSet& gram_;
  Eigen::VectorXd prior_;
  std::map<std::string, std::vector<double>> fold_sse_;
};

// A design with structure outside the vocabulary as a nuisance beside the
// frame (structure_nuisance.h), free as the frame is, and the prior of the
// effects' columns kept.
struct WithStructure {
  WithStructure(const Design& d, const Eigen::VectorXd& effect_prior, const Eigen::MatrixXd& extra)
      : design(WithNuisance(d, extra)),
        gram(design, MakeFolds(design)),
        prior(Eigen::VectorXd::Zero(design.parameters())) {
    const Eigen::Index effect_columns = d.parameters() - (d.frame.begin + d.frame.count);
    prior.tail(effect_columns) = effect_prior.tail(effect_columns);
  }
  Design design;
  GramSet gram;
  Eigen::VectorXd prior;
};

// Whether `e` earns its place among `selected` on `eval`, whose held-out
// MSE for `selected` is `cv`: the set without it is min_cv_gain worse held
// out, and `selected` beats it run by run (the paired test).
bool EarnsItsPlace(Evaluator& eval, double cv, const std::vector<Effect>& selected, Effect e, const DiagnoseOptions& o);

// The selected effects that no longer earn their place beside a structure
// that predicts the held-out runs `cv` (MSE): an effect that no longer cuts
// the error by min_cv_gain there, or no longer beats the model without it
// run by run. `own` (if any) is the structure's own effect and stays.
std::vector<Effect> RedundantBeside(Evaluator& with_structure, double cv, const std::vector<Effect>& selected,
                                    const DiagnoseOptions& o, std::optional<Effect> own = std::nullopt);

}  // namespace edsp::gap
