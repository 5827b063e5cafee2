#include "edsp/diagnosis/diagnose.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <map>
#include <numeric>
#include <optional>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "edsp/diagnosis/beyond_vocabulary.h"
#include "edsp/diagnosis/calibration_set.h"
#include "edsp/diagnosis/effect_sets.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/paired_test.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/diagnosis/robust_fit.h"
#include "edsp/diagnosis/structural_mode_fit.h"
#include "edsp/diagnosis/thermal_time_constant_fit.h"
#include "edsp/diagnosis/time_offset.h"

namespace edsp::gap {

namespace {

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

std::vector<std::string> AmbiguousWithNames(const EffectResult& r) {
  std::vector<std::string> names;
  for (Effect e : r.ambiguous_with) names.emplace_back(EffectName(e));
  // The pseudo-effect is named as the conclusion it makes (conclusion.h).
  if (r.ambiguous_with_unknown) names.emplace_back(ConclusionName(Conclusion::kUnknown));
  return names;
}

namespace {

// Forward selection (the effect that most cuts the held-out error, while it
// cuts it enough and BIC agrees), then backward (an effect the later ones
// made redundant goes again); explained fractions in the final order.
struct Selection {
  std::vector<Effect> effects;
  double cv0 = 0.0, cv = 0.0;    // held-out MSE: frame only, selected
  double rss0 = 0.0, rss = 0.0;  // in-sample SSE: frame only, selected
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

// Whether going from in-sample SSE `rss` to `rss_new` with `extra_parameters`
// more lowers BIC by at least min_bic_drop.
bool BicDrops(double n_res, double rss, double rss_new, int extra_parameters, const DiagnoseOptions& o) {
  const double change =
      n_res * std::log(std::max(rss_new, 1e-300) / std::max(rss, 1e-300)) + extra_parameters * std::log(n_res);
  return change <= -o.min_bic_drop;
}

// Backward elimination within `set`: out goes whichever effect the held-out
// error misses least, while the rest predicts without it within
// min_cv_gain or it does not beat the set without it run by run.
std::vector<Effect> Eliminate(Evaluator& eval, const DiagnoseOptions& o, std::vector<Effect> set) {
  double cv = eval.Cv(set);
  while (set.size() > 1) {
    std::optional<Effect> drop;
    double drop_cv = std::numeric_limits<double>::infinity();
    for (Effect e : set) {
      const double without = eval.Cv(Without(set, e));
      const bool missed =
          without >= cv / (1.0 - o.min_cv_gain) && eval.SignificantlyBetter(set, Without(set, e), o.significance);
      if (!missed && without < drop_cv) drop = e, drop_cv = without;
    }
    if (!drop) break;
    set = Without(set, *drop);
    cv = drop_cv;
  }
  return set;
}

// Effects that only predict together (joint centres, leg offsets and lead
// errors: each alone a poor stand-in for the others) are not reached one
// at a time: the whole vocabulary, eliminated backward the same way, wins
// over the forward path if it predicts the held-out runs clearly better and
// BIC agrees. Searched only where the whole vocabulary itself predicts them
// clearly better than the forward path (else the path missed nothing that
// effects explain together; the search costs some fifty fits of every
// column).
void PreferEliminatedWhole(Evaluator& eval, const DiagnoseOptions& o, double n_res, Selection* s) {
  if (!(eval.Cv(AllEffects()) < s->cv * (1.0 - o.min_cv_gain))) return;
  const std::vector<Effect> whole = Eliminate(eval, o, AllEffects());
  if (static_cast<int>(whole.size()) > o.max_effects) return;
  const double cv = eval.Cv(whole), rss = eval.Rss(whole);
  if (!(cv < s->cv * (1.0 - o.min_cv_gain))) return;
  int extra_parameters = 0;
  for (Effect e : whole) extra_parameters += ParameterCount(e);
  for (Effect e : s->effects) extra_parameters -= ParameterCount(e);
  if (!BicDrops(n_res, s->rss, rss, extra_parameters, o)) return;
  s->effects = whole;
  s->cv = cv;
  s->rss = rss;
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
    if (!BicDrops(n_res, s.rss, rss_new, ParameterCount(best), o)) break;
    s.effects.push_back(best);
    s.cv = best_cv;
    s.rss = rss_new;
  }
  s.effects = Eliminate(eval, o, s.effects);
  s.cv = eval.Cv(s.effects);
  s.rss = eval.Rss(s.effects);
  PreferEliminatedWhole(eval, o, n_res, &s);
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
      r.verdict = Verdict::kIdentified;
    } else {
      r.cv_gain = (s.cv - eval.Cv(With(s.effects, e))) / s.cv0;
      r.explained_fraction = (s.rss - eval.Rss(With(s.effects, e))) / s.rss0;
      r.verdict = Verdict::kRejected;
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
      // A tie only where the runs cannot tell the two apart: an effect that
      // predicts the held-out runs better than its alternative run by run
      // (the paired test of selection) is not ambiguous with it.
      const auto e_over_alt = [&] { return LogGains(eval.FoldSse(s.effects), eval.FoldSse(With(rest, alt))); };
      if (!Tied(alt_gain, gain, e_over_alt, o)) continue;
      for (auto [a, b] : {std::pair{e, alt}, std::pair{alt, e}}) {
        EffectResult& r = results[a];
        r.verdict = Verdict::kAmbiguous;
        r.ambiguous_with.push_back(b);
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

// The calibration's effects fitted together on every run: the selected
// effects' fit when they are the set, else the same robust fit of its own.
CalibrationResult FitCalibration(const Design& d, const GramSet& gram, const Eigen::VectorXd& prior,
                                 const CalibrationSet& set, const std::map<Effect, EffectResult>& results,
                                 const std::vector<Effect>& selected, double noise_floor_rms_m) {
  CalibrationResult out;
  out.effects = set.effects;
  out.chosen_by = set.chosen_by;
  out.heldout_rms_m = std::sqrt(3.0 * set.cv_mse);
  out.identified_heldout_rms_m = std::sqrt(3.0 * set.identified_cv_mse);
  const bool is_selected =
      set.effects.size() == selected.size() &&
      std::all_of(set.effects.begin(), set.effects.end(), [&](Effect e) { return Contains(selected, e); });
  const Columns cols = ColumnsOf(d, set.effects);
  const Columns effect_cols(cols.begin() + 6, cols.end());
  // The σ saved with the model (what edsp-gap drift compares a later
  // session with) is at least the jackknife's over the runs' parts: on a
  // whole rig the formal σ takes the model for the rig.
  const Eigen::VectorXd jackknife =
      JackknifeSigma(gram, cols, prior).tail(static_cast<Eigen::Index>(effect_cols.size()));
  int at = 0;
  if (is_selected) {
    for (Effect e : set.effects) {
      out.theta.push_back(results.at(e).theta);
      out.sigma.push_back(results.at(e).sigma.cwiseMax(jackknife.segment(at, ParameterCount(e))));
      at += ParameterCount(e);
    }
    return out;
  }
  const Eigen::VectorXd theta = gram.Solve(cols, gram.AllFolds(), prior);
  const RobustFit robust = FitRobust(d, effect_cols, theta.tail(static_cast<Eigen::Index>(effect_cols.size())),
                                     3.0 * std::max(noise_floor_rms_m, 1e-7), prior);
  for (Effect e : set.effects) {
    out.theta.push_back(robust.theta.segment(at, ParameterCount(e)));
    out.sigma.push_back(robust.sigma.segment(at, ParameterCount(e)).cwiseMax(jackknife.segment(at, ParameterCount(e))));
    at += ParameterCount(e);
  }
  return out;
}

// The first effect of a calibration whose fit is not a real platform's
// (calibration::ParameterLimit: the kinematics would refuse the model).
std::optional<Effect> BeyondAPlatform(const CalibrationResult& c) {
  for (std::size_t k = 0; k < c.effects.size(); ++k) {
    if (!(c.theta[k].cwiseAbs().maxCoeff() <= calibration::ParameterLimit(c.effects[k]))) return c.effects[k];
  }
  return std::nullopt;
}

// The calibration set (calibration_set.h) and its fit; an effect whose fit
// beside the others a platform cannot have is left out and the set chosen
// again without it.
//
// Chosen after the checks beyond the vocabulary: an effect they find
// ambiguous with `unknown` (a lag the encoders do not show, a drifting clock
// or structure that does as well) is what no calibration applies, in any
// set; one that only stands in for a base tilting under the payload may be
// applied, as a predictor of what the tilt does to the platform.
CalibrationResult CalibrationOf(const Design& d, const GramSet& gram, const Eigen::VectorXd& prior, Evaluator& eval,
                                const Diagnosis& diagnosis, double noise_floor_rms_m) {
  std::map<Effect, EffectResult> results;
  std::vector<Effect> identified, excluded;
  for (const EffectResult& r : diagnosis.effects) {
    results[r.effect] = r;
    if (r.verdict == Verdict::kIdentified && Contains(diagnosis.selected, r.effect)) identified.push_back(r.effect);
    if (r.ambiguous_with_unknown && !r.stands_in_for_mechanics) excluded.push_back(r.effect);
  }
  const std::vector<Effect>& selected = diagnosis.selected;
  for (;;) {
    CalibrationResult c = FitCalibration(d, gram, prior, ChooseCalibrationSet(eval, identified, selected, excluded),
                                         results, selected, noise_floor_rms_m);
    const std::optional<Effect> absurd = BeyondAPlatform(c);
    if (!absurd || c.effects.empty()) return c;
    excluded.push_back(*absurd);
  }
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
  StructureOptions bars = o.structure;
  bars.min_run_offset_share = o.min_cv_gain;  // runs apart matter as an effect's cut does
  out->structure = AnalyseStructure(d, residual, heldout, bars);
  const bool effects = !out->selected.empty();
  out->conclusion = Conclude(effects, out->structure.structured);
  out->unexplained_note =
      out->structure.structured
          ? "structure that no effect of the vocabulary explains: " + out->structure.Describe()
          : fmt::format(
                "white within the tracker's noise ({:.1f} µm RMS left, floor {:.1f} µm; {:.0f}% of the "
                "held-out residual above its white level)",
                out->unexplained.rms_m * 1e6, out->noise_floor_rms_m * 1e6, 100 * out->structure.structured_share);
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
  out->shrink = Shrink(out->holdout_before.rms_m, out->holdout_after.rms_m);
  out->gap_shrink = GapShrink(out->holdout_before.rms_m, out->holdout_after.rms_m, out->noise_floor_rms_m);
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
  out.has_encoder = d.has_encoder;
  out.drives_described_rms_m = d.drives_described_rms_m;
  out.drives_rest_rms_m = d.drives_rest_rms_m;
  out.drives_rest_taken_out = d.drives_rest_taken_out;
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

  out.prior_sigma2 = PriorVariance(d, out.noise_floor_rms_m);
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
  CheckBeyondTheVocabulary(d, prior, eval, o, &out);
  out.calibration = CalibrationOf(d, gram, prior, eval, out, out.noise_floor_rms_m);
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
                     [&](const EffectResult& r) { return r.effect == effect && r.verdict != Verdict::kRejected; });
}

// Backlash's play operator needs the play's width, which is what the fit
// estimates: once found, the diagnosis runs again with the estimate.
Diagnosis WithBacklashWidth(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                            Diagnosis d) {
  for (const EffectResult& r : d.effects) {
    if (r.effect != Effect::kBacklash || r.verdict == Verdict::kRejected || r.theta.size() != 6) continue;
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
  const ThermalTimeConstantChoice tau =
      ChooseThermalTimeConstant(model, Decimated(data, options.max_rate_hz), d.design, options.thermal_time_constants_s,
                                scored, d.prior_sigma2, d.time_offset);
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

// Step 0 judges a step beside the vocabulary's effects, the structural
// mode's among them only once its frequency is known: a sway left in the
// residual along a step's signature turns the step away as structure. So
// where a step was turned away for structure, the mode that best predicts
// the held-out runs beside the frame is found and the search runs again
// with it; its events are taken if it finds any.
ChangeSearch SearchChanges(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                           MeasurementData* after) {
  const MeasurementData thinned = Decimated(data, options.max_rate_hz);
  ChangeSearch search = FindChanges(model, thinned, options.design, options.changes, after);
  const bool structure = std::any_of(search.rejected.begin(), search.rejected.end(),
                                     [](const ChangeEvent& e) { return e.alternative == StepRejection::kStructure; });
  if (!structure || !options.fit_structural_mode || options.design.structural_mode_hz > 0.0) return search;
  const Design design = BuildDesign(model, thinned, options.design);
  const double sigma_axis = std::max(NoiseFloorRms(design) / std::sqrt(3.0), 1e-8);
  const StructuralModeChoice mode = ChooseStructuralMode(design, {}, sigma_axis * sigma_axis, 0.0);
  if (mode.cv_gain < options.min_cv_gain) return search;
  DesignOptions with_mode = options.design;
  with_mode.structural_mode_hz = mode.hz;
  with_mode.structural_mode_damping = mode.damping;
  MeasurementData again_after;
  ChangeSearch again = FindChanges(model, thinned, with_mode, options.changes, &again_after);
  if (again.events.empty()) return search;
  again.seconds += search.seconds;
  again.structural_mode_hz = mode.hz;
  *after = std::move(again_after);
  return again;
}

}  // namespace

Diagnosis Diagnose(const PlatformModel& model, const MeasurementData& recorded, const DiagnoseOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  double correction_rms_m = 0.0;
  const bool corrected = CarriesACorrection(recorded);
  const MeasurementData nominal =
      corrected ? AsCommandedNominally(model, recorded, &correction_rms_m) : MeasurementData{};
  const MeasurementData& as_recorded = corrected && options.against == Against::kNominal ? nominal : recorded;
  // A rig that changed within the session is diagnosed as it is after the
  // change (the rows before it moved to that rig); the change is reported.
  MeasurementData as_after;
  ChangeSearch changes = SearchChanges(model, as_recorded, options, &as_after);
  const MeasurementData& data = changes.events.empty() ? as_recorded : as_after;
  const double reading_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Diagnosis d = WithStructuralMode(model, data, options,
                                   WithBacklashWidth(model, data, options, DiagnoseOnce(model, data, options)));
  d = WithThermalTimeConstant(model, data, options, std::move(d));
  d.changes = std::move(changes);
  d.against = options.against;
  d.recorded_correction_rms_m = correction_rms_m;
  d.seconds += reading_s;
  return d;
}

}  // namespace edsp::gap
