#include "edsp/diagnosis/diagnose.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>

#include <Eigen/Eigenvalues>
#include <boost/math/distributions/students_t.hpp>
#include <fmt/format.h>

#include "edsp/diagnosis/encoder_check.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/diagnosis/robust_fit.h"
#include "edsp/diagnosis/structural_mode_fit.h"
#include "edsp/diagnosis/structure_nuisance.h"
#include "edsp/diagnosis/thermal_time_constant_fit.h"
#include "edsp/diagnosis/time_offset.h"

namespace edsp::gap {

namespace {

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

template <typename T>
bool Contains(const std::vector<T>& set, const T& e) {
  return std::find(set.begin(), set.end(), e) != set.end();
}

// Each fold's log ratio of its held-out squared error without and with.
std::vector<double> LogGains(const std::vector<double>& with_sse, const std::vector<double>& without_sse) {
  std::vector<double> gain;
  for (std::size_t k = 0; k < with_sse.size(); ++k) {
    gain.push_back(std::log(std::max(without_sse[k], 1e-300) / std::max(with_sse[k], 1e-300)));
  }
  return gain;
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

// Share of an effect's signature the frame can reproduce: per column, the
// part of its norm in the span of the frame's columns; the mean over columns.
double FrameOverlap(const Design& d, const GramSet& gram, Effect e) {
  const Columns frame = ColumnsOf(d, {});
  const ColumnRange& r = d.Of(e);
  Columns own;
  for (int k = 0; k < r.count; ++k) own.push_back(r.begin + k);
  const std::vector<int> all = gram.AllFolds();
  const Eigen::MatrixXd Hff = gram.Gram(frame, frame, all);
  const Eigen::MatrixXd Hfe = gram.Gram(frame, own, all);
  const Eigen::MatrixXd Hee = gram.Gram(own, own, all);
  const Eigen::MatrixXd projected = Hfe.transpose() * Hff.ldlt().solve(Hfe);
  double overlap = 0.0;
  int used = 0;
  for (Eigen::Index k = 0; k < Hee.rows(); ++k) {
    if (Hee(k, k) <= 0.0) continue;
    overlap += std::clamp(projected(k, k) / Hee(k, k), 0.0, 1.0);
    ++used;
  }
  return used ? overlap / used : 0.0;
}

// Before trusting a fit: the stacked (column-scaled) Jacobian's condition
// number, and for each selected effect its strongest parameter correlation
// with another selected effect or the tracker frame.
void Identifiability(const Design& d, const GramSet& gram, const Eigen::VectorXd& prior,
                     const std::vector<Effect>& selected, std::map<Effect, EffectResult>* results,
                     double* condition_number) {
  const Columns cols = ColumnsOf(d, selected);
  const std::vector<int> all = gram.AllFolds();
  Eigen::MatrixXd H = gram.Gram(cols, cols, all);
  const Eigen::VectorXd scale = H.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd S = scale.asDiagonal() * H * scale.asDiagonal();
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues().cwiseMax(0.0);
  *condition_number = lambda.minCoeff() > 0.0 ? std::sqrt(lambda.maxCoeff() / lambda.minCoeff())
                                              : std::numeric_limits<double>::infinity();
  const Eigen::MatrixXd cov = gram.Covariance(cols, all, prior, 1.0);
  std::vector<std::string> owner(6, "tracker_frame");
  for (Effect e : selected) owner.insert(owner.end(), static_cast<std::size_t>(ParameterCount(e)), EffectName(e));
  for (Effect e : selected) {
    EffectResult& r = (*results)[e];
    for (Eigen::Index a = 0; a < cov.rows(); ++a) {
      if (owner[static_cast<std::size_t>(a)] != EffectName(e)) continue;
      for (Eigen::Index b = 0; b < cov.rows(); ++b) {
        if (owner[static_cast<std::size_t>(b)] == EffectName(e) || cov(a, a) <= 0.0 || cov(b, b) <= 0.0) continue;
        const double c = std::abs(cov(a, b)) / std::sqrt(cov(a, a) * cov(b, b));
        if (c > r.max_correlation) r.max_correlation = c, r.correlated_with = owner[static_cast<std::size_t>(b)];
      }
    }
  }
}

}  // namespace

namespace {

// Student's t on the mean gain, one-sided.
bool MeanGainIsSignificant(const std::vector<double>& gain, double alpha) {
  const std::size_t n = gain.size();
  const double mean = std::accumulate(gain.begin(), gain.end(), 0.0) / static_cast<double>(n);
  if (n < 2 || mean <= 0.0) return mean > 0.0;
  double var = 0.0;
  for (double g : gain) var += (g - mean) * (g - mean);
  var /= static_cast<double>(n - 1);
  if (var <= 0.0) return true;
  const double t = mean / std::sqrt(var / static_cast<double>(n));
  const boost::math::students_t dist(static_cast<double>(n - 1));
  return t > boost::math::quantile(boost::math::complement(dist, alpha));
}

}  // namespace

double SignedRankPValue(const std::vector<double>& gain) {
  std::vector<double> nonzero;
  for (double g : gain) {
    if (g != 0.0) nonzero.push_back(g);
  }
  const int n = static_cast<int>(nonzero.size());
  if (n == 0) return 1.0;
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return std::abs(nonzero[static_cast<std::size_t>(a)]) < std::abs(nonzero[static_cast<std::size_t>(b)]);
  });
  int w_plus = 0;
  for (int r = 0; r < n; ++r) w_plus += nonzero[static_cast<std::size_t>(order[static_cast<std::size_t>(r)])] > 0.0 ? r + 1 : 0;
  // ways[w]: subsets of the ranks 1..n summing to w.
  const int total = n * (n + 1) / 2;
  std::vector<double> ways(static_cast<std::size_t>(total + 1), 0.0);
  ways[0] = 1.0;
  for (int r = 1; r <= n; ++r) {
    for (int w = total; w >= r; --w) ways[static_cast<std::size_t>(w)] += ways[static_cast<std::size_t>(w - r)];
  }
  double at_least = 0.0;
  for (int w = w_plus; w <= total; ++w) at_least += ways[static_cast<std::size_t>(w)];
  return at_least / std::pow(2.0, n);
}

bool PairedGainIsSignificant(const std::vector<double>& gain, double alpha) {
  if (gain.empty()) return false;
  if (MeanGainIsSignificant(gain, alpha)) return true;
  return static_cast<int>(gain.size()) >= kMinRunsForSignedRank && SignedRankPValue(gain) <= kSignedRankLevel;
}

double NoiseFloorRms(const Design& d) {
  std::vector<double> diffs, all;
  for (const ColumnRange& run : d.run_samples) {
    for (int k = run.begin + 1; k < run.begin + run.count; ++k) {
      const bool rest = d.leg_velocity_m_s[static_cast<std::size_t>(k)].cwiseAbs().maxCoeff() < 1e-5 &&
                        d.leg_velocity_m_s[static_cast<std::size_t>(k - 1)].cwiseAbs().maxCoeff() < 1e-5;
      for (int axis = 0; axis < 3; ++axis) {
        const double diff = d.residual(3 * k + axis) - d.residual(3 * (k - 1) + axis);
        all.push_back(std::abs(diff));
        if (rest) diffs.push_back(std::abs(diff));
      }
    }
  }
  std::vector<double>& use = diffs.size() >= 150 ? diffs : all;
  if (use.empty()) return 0.0;
  std::nth_element(use.begin(), use.begin() + static_cast<std::ptrdiff_t>(use.size() / 2), use.end());
  const double mad = use[use.size() / 2];
  // |a − b| of two N(0, σ²) samples has median 0.6745·√2·σ.
  const double sigma = mad / (0.6745 * std::sqrt(2.0));
  return std::sqrt(3.0) * sigma;
}

namespace {

// Forward selection (the effect that most cuts the held-out error, while it
// cuts it enough and BIC agrees), then backward (an effect the later ones
// made redundant goes again); explained fractions in the final order.
struct Selection {
  std::vector<Effect> effects;
  double cv0 = 0.0, cv = 0.0;      // held-out MSE: frame only, selected
  double rss0 = 0.0, rss = 0.0;    // in-sample SSE: frame only, selected
  std::map<Effect, double> explained;
};

bool Nested(Effect a, Effect b) { return IsNestedIn(a, b) || IsNestedIn(b, a); }

// Of a nested pair (effects.h), the simpler unless the richer is clearly
// better on held-out runs, whichever of the two selection took.
void PreferByNesting(Evaluator& eval, const DiagnoseOptions& o, Selection* s) {
  for (Effect& chosen : s->effects) {
    for (Effect other : AllEffects()) {
      if (!Nested(chosen, other) || Contains(s->effects, other)) continue;
      const std::vector<Effect> rest = Without(s->effects, chosen);
      const Effect simple = IsNestedIn(chosen, other) ? chosen : other;
      const Effect rich = simple == chosen ? other : chosen;
      const double cv_simple = eval.Cv(With(rest, simple)), cv_rich = eval.Cv(With(rest, rich));
      const Effect preferred = cv_rich < cv_simple * (1.0 - o.nested_gain) ? rich : simple;
      if (preferred == chosen) continue;
      std::vector<Effect> swapped = rest;
      swapped.push_back(preferred);
      chosen = preferred;
      s->cv = eval.Cv(swapped);
    }
  }
}

Selection SelectEffects(Evaluator& eval, const DiagnoseOptions& o, double n_res) {
  Selection s;
  s.cv0 = s.cv = eval.Cv({});
  s.rss0 = s.rss = eval.Rss({});
  while (static_cast<int>(s.effects.size()) < o.max_effects) {
    Effect best = Effect::kLegOffset;
    double best_cv = s.cv;
    for (Effect e : AllEffects()) {
      if (Contains(s.effects, e)) continue;
      const double c = eval.Cv(With(s.effects, e));
      if (c < best_cv && eval.SignificantlyBetter(With(s.effects, e), s.effects, o.significance)) best_cv = c, best = e;
    }
    if (best_cv >= s.cv * (1.0 - o.min_cv_gain)) break;
    const double rss_new = eval.Rss(With(s.effects, best));
    const double bic_change = n_res * std::log(std::max(rss_new, 1e-300) / std::max(s.rss, 1e-300)) +
                              ParameterCount(best) * std::log(n_res);
    if (bic_change > -o.min_bic_drop) break;
    s.effects.push_back(best);
    s.cv = best_cv;
    s.rss = rss_new;
  }
  for (bool removed = true; removed && s.effects.size() > 1;) {
    removed = false;
    for (Effect e : s.effects) {
      const double without = eval.Cv(Without(s.effects, e));
      if (without < s.cv / (1.0 - o.min_cv_gain) ||
          !eval.SignificantlyBetter(s.effects, Without(s.effects, e), o.significance)) {
        s.effects = Without(s.effects, e);
        s.cv = without;
        removed = true;
        break;
      }
    }
  }
  PreferByNesting(eval, o, &s);
  s.rss = eval.Rss(s.effects);
  std::vector<Effect> so_far;
  double before = s.rss0;
  for (Effect e : s.effects) {
    so_far.push_back(e);
    const double after = eval.Rss(so_far);
    s.explained[e] = (before - after) / s.rss0;
    before = after;
  }
  return s;
}

// Verdicts: a selected effect that another could replace for most of its
// gain, and that does not beat that other run by run, is ambiguous, and
// both are named; the others are rejected.
std::map<Effect, EffectResult> Verdicts(Evaluator& eval, const Selection& s, const DiagnoseOptions& o) {
  std::map<Effect, EffectResult> results;
  for (Effect e : AllEffects()) {
    EffectResult r;
    r.effect = e;
    if (Contains(s.effects, e)) {
      r.cv_gain = (eval.Cv(Without(s.effects, e)) - s.cv) / s.cv0;
      r.explained_fraction = s.explained.at(e);
      r.verdict = "identified";
    } else {
      r.cv_gain = (s.cv - eval.Cv(With(s.effects, e))) / s.cv0;
      r.explained_fraction = (s.rss - eval.Rss(With(s.effects, e))) / s.rss0;
      r.verdict = "rejected";
    }
    results[e] = r;
  }
  for (Effect e : s.effects) {
    const std::vector<Effect> rest = Without(s.effects, e);
    const double base = eval.Cv(rest);
    const double gain = (base - s.cv) / base;  // what e adds to the others
    for (Effect alt : AllEffects()) {
      if (Contains(s.effects, alt) || Nested(e, alt)) continue;
      const double alt_gain = (base - eval.Cv(With(rest, alt))) / base;
      if (alt_gain < std::max(o.min_cv_gain, o.ambiguity_ratio * gain)) continue;
      // A tie only where the runs cannot tell the two apart: an effect that
      // predicts the held-out runs better than its alternative run by run
      // (the paired test of selection) is not ambiguous with it.
      if (eval.SignificantlyBetter(s.effects, With(rest, alt), o.significance)) continue;
      for (auto [a, b] : {std::pair{e, alt}, std::pair{alt, e}}) {
        EffectResult& r = results[a];
        r.verdict = "ambiguous";
        r.ambiguous_with.push_back(EffectName(b));
        r.next_measurement = SeparatingMeasurement(a, b);
      }
    }
  }
  return results;
}

// The selected model on every run, refined with Ceres (exact frame rotation,
// Huber loss): parameters and uncertainties into `results`, the frame and
// the fit's summary into `out`; returns the residual. Rejected effects get
// the linear fit's values for what they would have been beside the others.
Eigen::VectorXd FitSelected(const Design& d, const GramSet& gram, const Eigen::VectorXd& prior, const Selection& s,
                            Diagnosis* out, std::map<Effect, EffectResult>* results) {
  const std::vector<int> all = gram.AllFolds();
  const Columns cols = ColumnsOf(d, s.effects);
  const Eigen::VectorXd theta = gram.Solve(cols, all, prior);
  const Columns effect_cols(cols.begin() + 6, cols.end());
  const RobustFit robust = FitRobust(d, effect_cols, theta.tail(static_cast<Eigen::Index>(effect_cols.size())),
                                     3.0 * std::max(out->noise_floor_rms_m, 1e-7), prior);
  out->robust = {robust.huber_m, robust.iterations, robust.converged, robust.covariance_ok};
  out->frame = Eigen::VectorXd(6);
  out->frame << robust.frame.tail(3), robust.frame.head(3);
  int at = 0;
  for (Effect e : s.effects) {
    const int p = ParameterCount(e);
    (*results)[e].theta = robust.theta.segment(at, p);
    (*results)[e].sigma = robust.sigma.segment(at, p);
    at += p;
  }
  const double dof = std::max(1.0, gram.Residuals(all) - static_cast<double>(cols.size()));
  for (Effect e : AllEffects()) {
    if (Contains(s.effects, e)) continue;
    const Columns c = ColumnsOf(d, With(s.effects, e));
    (*results)[e].theta = gram.Solve(c, all, prior).tail(ParameterCount(e));
    (*results)[e].sigma =
        gram.Covariance(c, all, prior, s.rss / dof).diagonal().tail(ParameterCount(e)).cwiseMax(0.0).cwiseSqrt();
  }
  return robust.residual;
}

// Selected effects in selection order, then the others by what they would add.
std::vector<EffectResult> Ranked(const std::map<Effect, EffectResult>& results, const std::vector<Effect>& selected) {
  std::vector<EffectResult> ranked, others;
  for (Effect e : selected) ranked.push_back(results.at(e));
  for (Effect e : AllEffects()) {
    if (!Contains(selected, e)) others.push_back(results.at(e));
  }
  std::stable_sort(others.begin(), others.end(),
                   [](const EffectResult& a, const EffectResult& b) { return a.cv_gain > b.cv_gain; });
  ranked.insert(ranked.end(), others.begin(), others.end());
  return ranked;
}

// What is left: white noise, or structure nobody explains (judged on the
// held-out residual, residual_structure.h), whatever its size.
void DescribeRest(const Design& d, const Eigen::VectorXd& residual, const Eigen::VectorXd& heldout,
                  const DiagnoseOptions& o, Diagnosis* out) {
  out->unexplained = PointStats(residual, 0, d.samples());
  out->whiteness = TestWhiteness(d, residual);
  out->structure = AnalyseStructure(d, residual, heldout, o.structure);
  const bool effects = !out->selected.empty();
  out->conclusion = out->structure.structured ? (effects ? "effects+unknown" : "unknown") : (effects ? "effects" : "none");
  out->unexplained_note =
      out->structure.structured
          ? "structure that no effect of the vocabulary explains: " + out->structure.Describe()
          : fmt::format("white within the tracker's noise ({:.1f} µm RMS left, floor {:.1f} µm; {:.0f}% of the "
                        "held-out residual above its white level)",
                        out->unexplained.rms_m * 1e6, out->noise_floor_rms_m * 1e6,
                        100 * out->structure.structured_share);
}

// A design with structure outside the vocabulary as a nuisance beside the
// frame (structure_nuisance.h), free as the frame is, and the prior of the
// effects' columns kept.
struct WithStructure {
  WithStructure(const Design& d, const Eigen::VectorXd& effect_prior, const Eigen::MatrixXd& extra)
      : design(WithNuisance(d, extra)), gram(design, MakeFolds(design)), prior(Eigen::VectorXd::Zero(design.parameters())) {
    const Eigen::Index effect_columns = d.parameters() - (d.frame.begin + d.frame.count);
    prior.tail(effect_columns) = effect_prior.tail(effect_columns);
  }
  Design design;
  GramSet gram;
  Eigen::VectorXd prior;
};

// The selected effects that no longer earn their place beside a structure
// that predicts the held-out runs `cv` (MSE): an effect that no longer cuts
// the error by min_cv_gain there, or no longer beats the model without it
// run by run. `own` (if any) is the structure's own effect and stays.
std::vector<Effect> RedundantBeside(Evaluator& with_structure, double cv, const std::vector<Effect>& selected,
                                    const DiagnoseOptions& o, std::optional<Effect> own = std::nullopt) {
  std::vector<Effect> explained;
  for (Effect e : selected) {
    if (e == own) continue;
    const std::vector<Effect> rest = Without(selected, e);
    const double base = with_structure.Cv(rest);
    const bool gains = base > 0.0 && (base - cv) / base >= o.min_cv_gain;
    if (!gains || !with_structure.SignificantlyBetter(selected, rest, o.significance)) explained.push_back(e);
  }
  return explained;
}

// Selected effects whose held-out gain the residual's structure could also
// explain. The structure is modelled as a mode at the candidate frequency
// that predicts the held-out runs best; if that mode cuts the selected
// model's held-out error by min_cv_gain, an effect that then no longer does
// so itself, or no longer beats the model without it run by run, is one the
// structure explains as well.
std::vector<Effect> ExplainedByStructure(const Design& d, const Eigen::VectorXd& prior, Evaluator& plain,
                                         const std::vector<Effect>& selected, const ResidualStructure& structure,
                                         const DiagnoseOptions& o) {
  std::vector<Effect> explained;
  if (!structure.structured || selected.empty()) return explained;
  double best_cv = plain.Cv(selected) * (1.0 - o.min_cv_gain);
  std::unique_ptr<WithStructure> best;
  for (double hz : CandidateModeFrequencies(structure)) {
    auto mode = std::make_unique<WithStructure>(d, prior, StructureColumns(d, hz, kAssumedDamping));
    const double cv = Evaluator(mode->design, mode->gram, mode->prior).Cv(selected);
    if (cv < best_cv) best_cv = cv, best = std::move(mode);
  }
  if (best == nullptr) return explained;  // no mode is what is left
  Evaluator eval(best->design, best->gram, best->prior);
  // The mode is structural_resonance's own signature.
  return RedundantBeside(eval, best_cv, selected, o, Effect::kStructuralResonance);
}

// Whether the base tilts under the payload's moment, beside the selected
// effects: the tilt's terms (structure_nuisance.h) cut their held-out error
// by min_cv_gain, and run by run. Then the selected effects that no longer
// earn their place beside it (compliance and joint centres taking up the
// tilt) go to `explained`.
BaseTiltCheck TestBaseTilt(const Design& d, const Eigen::VectorXd& prior, Evaluator& plain,
                           const std::vector<Effect>& selected, const DiagnoseOptions& o,
                           std::vector<Effect>* explained) {
  BaseTiltCheck c;
  if (!Contains(selected, Effect::kCompliance) && !Contains(selected, Effect::kJointPosition)) return c;
  c.tested = true;
  WithStructure tilt(d, prior, BaseTiltColumns(d));
  Evaluator eval(tilt.design, tilt.gram, tilt.prior);
  const double before = plain.Cv(selected), after = eval.Cv(selected);
  c.cv_gain = before > 0.0 ? (before - after) / before : 0.0;
  c.tilts = c.cv_gain >= o.min_cv_gain &&
            PairedGainIsSignificant(LogGains(eval.FoldSse(selected), plain.FoldSse(selected)), o.significance);
  if (c.tilts) *explained = RedundantBeside(eval, after, selected, o);
  return c;
}

// Whether the tracker's clock drifts from the controller's, beside the
// selected effects and a constant offset (time_offset.h). The drift ρ must
// stand out of its own uncertainty (|ρ| > kTimeOffsetSignificance·σ, as the
// offset must) and cut the held-out error run by run; then it drifts if
// the cut is min_cv_gain, or if a selected effect no longer earns its place
// beside the drifting clock (a servo lag equal on every leg that only the
// clock's mean made: the constant offset beside it takes that up too, so
// this arm rests on ρ's own evidence). Those effects go to `explained`.
ClockDriftCheck TestClockDrift(const Design& d, const Eigen::VectorXd& prior, const std::vector<Effect>& selected,
                               const DiagnoseOptions& o, std::vector<Effect>* explained) {
  ClockDriftCheck c;
  if (d.samples() == 0) return c;
  c.tested = true;
  const Eigen::MatrixXd clock = DriftingOffsetColumns(d);
  WithStructure steady(d, prior, clock.leftCols(1));
  WithStructure drifting(d, prior, clock);
  Evaluator still(steady.design, steady.gram, steady.prior), eval(drifting.design, drifting.gram, drifting.prior);
  const double before = still.Cv(selected), after = eval.Cv(selected);
  c.cv_gain = before > 0.0 ? (before - after) / before : 0.0;

  const Columns cols = ColumnsOf(drifting.design, selected);
  const std::vector<int> all = drifting.gram.AllFolds();
  const Eigen::VectorXd theta = drifting.gram.Solve(cols, all, drifting.prior);
  const int at = drifting.design.frame.count + drifting.design.nuisance.count - 1;  // ρ: the nuisance's last column
  const double sigma2 =
      drifting.gram.Sse(cols, theta, all) / std::max(1, drifting.gram.Residuals(all) - static_cast<int>(cols.size()));
  c.drift = theta(at);
  const Eigen::VectorXd rest = drifting.design.residual - drifting.design.columns(Eigen::all, cols) * theta;
  c.sigma = std::sqrt(std::max(0.0, drifting.gram.Covariance(cols, all, drifting.prior, sigma2)(at, at)) *
                      CorrelationInflation(rest));

  c.run_by_run = c.cv_gain > 0.0 && std::abs(c.drift) > kTimeOffsetSignificance * c.sigma &&
                 PairedGainIsSignificant(LogGains(eval.FoldSse(selected), still.FoldSse(selected)), o.significance);
  if (!c.run_by_run) return c;
  *explained = RedundantBeside(eval, after, selected, o);
  c.drifts = c.cv_gain >= o.min_cv_gain || !explained->empty();
  if (!c.drifts) explained->clear();
  return c;
}

// `unknown` when every selected effect could be the unknown's, else the
// effects and the unknown.
void ConcludeWithUnknown(Diagnosis* out) {
  const bool all = std::all_of(out->effects.begin(), out->effects.end(), [&](const EffectResult& r) {
    return !Contains(out->selected, r.effect) || Contains(r.ambiguous_with, std::string("unknown"));
  });
  out->conclusion = all ? "unknown" : "effects+unknown";
}

// An effect the unknown could explain is not identified (so no calibration
// applies it by default): ambiguous with the unknown, `why` saying what the
// unknown is.
void MarkExplainedByUnknown(const std::vector<Effect>& explained, const std::string& why, Diagnosis* out) {
  if (explained.empty()) return;
  for (EffectResult& r : out->effects) {
    if (!Contains(explained, r.effect)) continue;
    r.verdict = "ambiguous";
    if (!Contains(r.ambiguous_with, std::string("unknown"))) r.ambiguous_with.push_back("unknown");
    if (!r.next_measurement.empty()) r.next_measurement += "; ";
    r.next_measurement += why;
  }
  ConcludeWithUnknown(out);
}

void MarkExplainedByStructure(const std::vector<Effect>& explained, Diagnosis* out) {
  MarkExplainedByUnknown(explained,
                         "what causes the unexplained structure (" + out->structure.Describe() +
                             "): a mode of it predicts the held-out runs as well as this effect does",
                         out);
}

// What is left names an unknown that a check found beside a residual that
// may itself look white: the unknowns the checks found lead, then what the
// residual is; beside structure they follow its description.
void NoteUnknown(const std::string& what, Diagnosis* out) {
  static const std::string kResidual = "; the selected effects leave a residual ";
  std::string& note = out->unexplained_note;
  const std::size_t residual = note.find(kResidual);
  if (residual != std::string::npos) note.insert(residual, "; " + what);
  else if (out->structure.structured) note += "; " + what;
  else note = what + kResidual + note;
}

// The base's tilt is outside the vocabulary: said in what is left, and an
// effect it makes redundant is ambiguous with it.
void MarkExplainedByBaseTilt(const std::vector<Effect>& explained, Diagnosis* out) {
  if (!out->base_tilt.tilts) return;
  const std::string what = fmt::format(
      "the base tilts under the payload's moment (a rotational give of the base mount or floor beside the selected "
      "effects predicts the held-out runs {:.0f}% better)",
      100 * out->base_tilt.cv_gain);
  NoteUnknown(what, out);
  MarkExplainedByUnknown(explained,
                         what + ", and this effect no longer earns its place beside it; an inclinometer on the base "
                                "tells the tilt apart",
                         out);
  if (out->conclusion == "effects") out->conclusion = "effects+unknown";
}

// A drifting tracker clock is outside the vocabulary: said in what is left,
// and an effect it makes redundant is ambiguous with it.
void MarkExplainedByClockDrift(const std::vector<Effect>& explained, Diagnosis* out) {
  if (!out->clock_drift.drifts) return;
  const std::string what = fmt::format(
      "the tracker's clock drifts from the controller's by {:+.2f} ppm ± {:.2f} (its readings grow {} over the "
      "session; predicts the held-out runs {:.0f}% better)",
      out->clock_drift.drift * 1e6, out->clock_drift.sigma * 1e6, out->clock_drift.drift > 0.0 ? "later" : "earlier",
      100 * out->clock_drift.cv_gain);
  NoteUnknown(what, out);
  MarkExplainedByUnknown(explained,
                         what + ", and this effect no longer earns its place beside it; trigger the tracker from the "
                                "controller's clock (or PTP) and measure again",
                         out);
  if (out->conclusion == "effects") out->conclusion = "effects+unknown";
  if (out->conclusion == "none") out->conclusion = "unknown";
}

// A selected servo_lag the encoders do not show is not the drives' lag
// (encoder_check.h): not identified, and something outside the vocabulary
// is at work.
void MarkLagNotInTheDrives(const Design& d, Diagnosis* out) {
  for (EffectResult& r : out->effects) {
    if (r.effect != Effect::kServoLag || !Contains(out->selected, r.effect)) continue;
    if (!d.has_encoder) break;
    const double share = r.encoder_share = EncoderShareOfLag(d, r.theta);
    r.encoder_checked = true;
    if (share >= kMinEncoderShareOfLag) break;
    NoteUnknown(fmt::format("the tracker sees a lag the encoders do not ({:.0f}% of it)", 100 * std::max(share, 0.0)),
                out);
    MarkExplainedByUnknown({Effect::kServoLag},
                           fmt::format("the encoders show {:.0f}% of this lag, so it lies after the motor: look for a "
                                       "structure swaying under the platform's acceleration (an accelerometer on A's "
                                       "mount)",
                                       100 * std::max(share, 0.0)),
                           out);
    break;
  }
}

// Before (frame only) and after (frame and the selected effects) on each run
// held out of the fit, pooled; returns the held-out residual after (3 per sample).
Eigen::VectorXd HoldOut(const Design& d, const GramSet& gram, const Eigen::VectorXd& prior, const Columns& cols,
                        Diagnosis* out) {
  Eigen::VectorXd heldout = Eigen::VectorXd::Zero(3 * d.samples());
  const Columns frame_cols = ColumnsOf(d, {});
  double before2 = 0.0, after2 = 0.0;
  int held = 0;
  for (int f = 0; f < gram.folds(); ++f) {
    const std::vector<int> train = gram.AllBut(f);
    const Eigen::VectorXd t0 = gram.Solve(frame_cols, train, prior);
    const Eigen::VectorXd t1 = gram.Solve(cols, train, prior);
    out->holdout_runs.push_back(gram.fold(f).name);
    for (const ColumnRange& s : gram.fold(f).samples) {
      for (int k = s.begin; k < s.begin + s.count; ++k) {
        const auto rows = d.columns.middleRows(3 * k, 3);
        const Vector3 r = d.residual.segment<3>(3 * k);
        const double b = (r - rows(Eigen::all, frame_cols) * t0).norm();
        heldout.segment<3>(3 * k) = r - rows(Eigen::all, cols) * t1;
        const double a = heldout.segment<3>(3 * k).norm();
        before2 += b * b, after2 += a * a, ++held;
        out->holdout_before.max_m = std::max(out->holdout_before.max_m, b);
        out->holdout_after.max_m = std::max(out->holdout_after.max_m, a);
      }
    }
  }
  out->holdout_before.rms_m = held ? std::sqrt(before2 / held) : 0.0;
  out->holdout_after.rms_m = held ? std::sqrt(after2 / held) : 0.0;
  out->shrink = out->holdout_before.rms_m > 0.0 ? 1.0 - out->holdout_after.rms_m / out->holdout_before.rms_m : 0.0;
  return heldout;
}

// `clock`: the tracker's time offset when an earlier pass over the same
// data estimated it (it does not depend on the bases' settings).
Diagnosis DiagnoseOnce(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& o,
                       const TimeOffset* clock = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  Design d = BuildDesign(model, Decimated(data, o.max_rate_hz), o.design);
  Diagnosis out;
  out.design = o.design;
  out.samples = d.samples();
  out.timing_excluded = data.timing_excluded;
  out.runs = d.runs;
  out.R0 = d.R0;
  out.t0 = d.t0;
  out.applied_pr = d.applied_pr;
  out.applied_pr_ratio = d.applied_pr_ratio;
  out.platform = calibration::PlatformFingerprint(model);
  out.noise_floor_rms_m = NoiseFloorRms(d);
  const double sigma_axis = std::max(out.noise_floor_rms_m / std::sqrt(3.0), 1e-8);
  out.time_offset = clock != nullptr ? *clock : EstimateTimeOffset(d, PriorWeights(d, sigma_axis * sigma_axis));
  if (out.time_offset.applied) RemoveTimeOffset(out.time_offset.offset_s, &d);
  const GramSet gram(d, MakeFolds(d));
  const std::vector<int> all = gram.AllFolds();
  const double n_res = gram.Residuals(all);

  // The gap before any effect: the frame alone, fitted on everything.
  const Columns frame_cols = ColumnsOf(d, {});
  const Eigen::VectorXd frame_only = gram.Solve(frame_cols, all, Eigen::VectorXd::Zero(d.parameters()));
  const Eigen::VectorXd baseline = d.residual - d.columns(Eigen::all, frame_cols) * frame_only;
  out.gap = SummarizeGap(d, baseline);

  // The prior's weight is set against what the model does not yet explain
  // (not only the noise): a systematic misfit must not push poorly excited
  // parameters (joint centres seen from a single axis) far beyond real rigs.
  const double mse0 = baseline.squaredNorm() / n_res;
  out.prior_sigma2 = std::max(sigma_axis * sigma_axis, mse0);
  const Eigen::VectorXd prior = PriorWeights(d, out.prior_sigma2);
  Evaluator eval(d, gram, prior);

  const Selection selection = SelectEffects(eval, o, n_res);
  out.selected = selection.effects;
  std::map<Effect, EffectResult> results = Verdicts(eval, selection, o);
  const Eigen::VectorXd residual = FitSelected(d, gram, prior, selection, &out, &results);
  for (auto& [e, r] : results) r.frame_overlap = FrameOverlap(d, gram, e);
  Identifiability(d, gram, prior, out.selected, &results, &out.condition_number);
  out.effects = Ranked(results, out.selected);
  const Eigen::VectorXd heldout = HoldOut(d, gram, prior, ColumnsOf(d, out.selected), &out);
  DescribeRest(d, residual, heldout, o, &out);
  MarkExplainedByStructure(ExplainedByStructure(d, prior, eval, out.selected, out.structure, o), &out);
  std::vector<Effect> tilt_explained;
  out.base_tilt = TestBaseTilt(d, prior, eval, out.selected, o, &tilt_explained);
  MarkExplainedByBaseTilt(tilt_explained, &out);
  std::vector<Effect> clock_explained;
  out.clock_drift = TestClockDrift(d, prior, out.selected, o, &clock_explained);
  MarkExplainedByClockDrift(clock_explained, &out);
  MarkLagNotInTheDrives(d, &out);
  for (int k = 0; k < d.samples(); ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    out.series.push_back({d.sample_run[s], d.time_s[s], d.displacement[s], baseline.segment<3>(3 * k).norm(),
                          residual.segment<3>(3 * k).norm()});
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

namespace {

bool Found(const Diagnosis& d, Effect effect) {
  return std::any_of(d.effects.begin(), d.effects.end(),
                     [&](const EffectResult& r) { return r.effect == effect && r.verdict != "rejected"; });
}

// Backlash's play operator needs the play's width, which is what the fit
// estimates: once found, the diagnosis runs again with the estimate.
Diagnosis WithBacklashWidth(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                            Diagnosis d) {
  for (const EffectResult& r : d.effects) {
    if (r.effect != Effect::kBacklash || r.verdict == "rejected" || r.theta.size() != 6) continue;
    const double width = std::clamp(r.theta.cwiseAbs().mean(), 2e-6, 1e-3);
    if (std::abs(width - options.design.backlash_width_m) < 0.25 * options.design.backlash_width_m) break;
    DiagnoseOptions again = options;
    again.design.backlash_width_m = width;
    const double first_seconds = d.seconds;
    d = DiagnoseOnce(model, data, again, &d.time_offset);
    d.seconds += first_seconds;
    break;
  }
  return d;
}

// The structural mode's frequency and damping are not linear parameters:
// the first pass runs without the mode (its columns zero), then the mode
// that best predicts the held-out runs beside what that pass selected is
// found (structural_mode_fit.h), and if it cuts their error by
// min_cv_gain the diagnosis runs again with it, where selection decides
// whether structural_resonance is in. Kept if it is.
Diagnosis WithStructuralMode(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                             Diagnosis d) {
  if (!options.fit_structural_mode || d.design.structural_mode_hz > 0.0) return d;
  Design design = BuildDesign(model, Decimated(data, options.max_rate_hz), d.design);
  if (d.time_offset.applied) RemoveTimeOffset(d.time_offset.offset_s, &design);
  const double sigma2 = d.prior_sigma2;
  const double peak_hz = d.structure.structured ? d.structure.dominant_hz : 0.0;
  const StructuralModeChoice mode = ChooseStructuralMode(design, d.selected, sigma2, peak_hz);
  if (mode.cv_gain < options.min_cv_gain) return d;
  DiagnoseOptions again = options;
  again.design = d.design;
  again.design.structural_mode_hz = mode.hz;
  again.design.structural_mode_damping = mode.damping;
  Diagnosis candidate = DiagnoseOnce(model, data, again, &d.time_offset);
  candidate.seconds += d.seconds;
  if (!Found(candidate, Effect::kStructuralResonance)) {
    d.seconds = candidate.seconds;
    return d;
  }
  return candidate;
}

// The screws' cooling time is the thermal basis's one non-linear
// parameter: once thermal drift is found, the time constant that predicts
// the held-out runs best beside the selected effects is chosen from a grid
// (thermal_time_constant_fit.h), and the diagnosis runs again at it, kept
// if it still finds the drift and predicts the held-out runs better.
Diagnosis WithThermalTimeConstant(const PlatformModel& model, const MeasurementData& data,
                                  const DiagnoseOptions& options, Diagnosis d) {
  if (options.thermal_time_constants_s.empty() || !Found(d, Effect::kThermalDrift)) return d;
  const auto start = std::chrono::steady_clock::now();
  // Scored beside the selected effects, the drift among them even where it
  // was only named as an alternative (ambiguous) to one of them.
  std::vector<Effect> scored = d.selected;
  if (!Contains(scored, Effect::kThermalDrift)) scored.push_back(Effect::kThermalDrift);
  const ThermalTimeConstantChoice tau = ChooseThermalTimeConstant(
      model, Decimated(data, options.max_rate_hz), d.design, options.thermal_time_constants_s, scored,
      d.prior_sigma2, d.time_offset);
  double seconds = d.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (tau.tau_s != d.design.thermal_time_constant_s) {
    DiagnoseOptions at = options;
    at.design = d.design;
    at.design.thermal_time_constant_s = tau.tau_s;
    Diagnosis candidate = DiagnoseOnce(model, data, at, &d.time_offset);
    seconds += candidate.seconds;
    if (Found(candidate, Effect::kThermalDrift) && candidate.holdout_after.rms_m < d.holdout_after.rms_m) {
      d = std::move(candidate);
    }
  }
  d.seconds = seconds;
  return d;
}

}  // namespace

Diagnosis Diagnose(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options) {
  Diagnosis d = WithStructuralMode(model, data, options,
                                   WithBacklashWidth(model, data, options, DiagnoseOnce(model, data, options)));
  return WithThermalTimeConstant(model, data, options, std::move(d));
}

}  // namespace edsp::gap
