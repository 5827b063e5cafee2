#include "edsp/diagnosis/drift.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/effect_sets.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/report.h"
#include "edsp/diagnosis/robust_fit.h"
#include "edsp/diagnosis/saved_model.h"
#include "edsp/diagnosis/time_offset.h"
#include "edsp/kinematics/calibration.h"

namespace edsp::gap {

namespace {

// The residual with the frame alone fitted (the frame is the data's own).
Eigen::VectorXd WithoutFrame(const Design& d, const Eigen::VectorXd& r) {
  const auto F = d.columns.leftCols(6);
  const Eigen::VectorXd x = (F.transpose() * F).ldlt().solve(F.transpose() * r);
  return r - F * x;
}

struct Fitted {
  std::map<Effect, Eigen::VectorXd> delta, sigma;  // per effect: its change and that change's 1-σ
};

// Each leg's length change (LegChange): the six offsets fitted from zero
// beside the frame and the parameters found changed (`changed`, design
// columns), everything else held at the baseline's. Beside the joint
// centres' 36 changes and the frame, a leg's length is not known to within
// 100 µm on a session's motions (they mimic it over a small workspace);
// beside every other effect's change, a lead error or a lag takes part of
// it; beside the frame alone it is known to a few µm.
std::vector<LegChange> LegLengths(const Design& d, const Columns& changed, double noise_floor_rms_m) {
  const GramSet gram(d, MakeFolds(d));
  const std::vector<int> all = gram.AllFolds();
  Columns cols = ColumnsOf(d, {});
  for (int c : changed) {
    if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
  }
  const ColumnRange& offsets = d.Of(Effect::kLegOffset);
  cols.erase(std::remove_if(cols.begin(), cols.end(),
                            [&](int c) { return c >= offsets.begin && c < offsets.begin + offsets.count; }),
             cols.end());
  for (int leg = 0; leg < 6; ++leg) cols.push_back(offsets.begin + leg);
  const double sigma_axis = std::max(noise_floor_rms_m / std::sqrt(3.0), 1e-8);
  const Eigen::VectorXd prior = PriorWeights(d, sigma_axis * sigma_axis);
  const Eigen::VectorXd theta = gram.Solve(cols, all, prior);
  const double sigma2 = gram.Sse(cols, theta, all) / std::max(1, gram.Residuals(all) - static_cast<int>(cols.size()));
  const Eigen::VectorXd rest = d.residual - d.columns(Eigen::all, cols) * theta;
  const Eigen::MatrixXd covariance = gram.Covariance(cols, all, prior, sigma2) * CorrelationInflation(rest);
  const Eigen::VectorXd jackknife = JackknifeSigma(gram, cols, prior);
  std::vector<LegChange> legs;
  const auto first = static_cast<Eigen::Index>(cols.size()) - 6;
  for (int leg = 0; leg < 6; ++leg) {
    const Eigen::Index k = first + leg;
    LegChange c;
    c.leg = leg + 1;
    c.change_m = theta(k);
    // √2: the baseline's own error in this length, which the model does
    // not save, taken as large as the session's (LegChange).
    c.sigma_m = std::sqrt(2.0) * std::max(std::sqrt(std::max(0.0, covariance(k, k))), jackknife(k));
    legs.push_back(c);
  }
  return legs;
}

// δ of every effect the baseline applies, fitted together on what the
// baseline leaves, with the diagnosis's ridge (towards no change) and its
// robust fit: the new session's estimate of each parameter beside all the
// others, so that a change one parameter cannot tell from another's shows
// as a large σ, not as a change. Its σ is the larger of the formal one and
// the jackknife's over the session's runs (folds: MakeFolds).
Fitted FitChange(const Design& d, const std::vector<Effect>& baseline, double noise_floor_rms_m) {
  Fitted fit;
  if (baseline.empty()) return fit;
  const GramSet gram(d, MakeFolds(d));
  const std::vector<int> all = gram.AllFolds();
  const Eigen::VectorXd prior = PriorWeights(d, PriorVariance(d, noise_floor_rms_m));
  const Columns cols = ColumnsOf(d, baseline);
  const Eigen::VectorXd theta = gram.Solve(cols, all, prior);
  const Columns effect_cols(cols.begin() + 6, cols.end());
  const RobustFit robust = FitRobust(d, effect_cols, theta.tail(static_cast<Eigen::Index>(effect_cols.size())),
                                     3.0 * std::max(noise_floor_rms_m, 1e-7), prior);
  // A residual that is not white (what no effect models, the baseline's
  // own misfit) holds fewer independent samples than rows: the σ grows as
  // for an AR(1) series (linear_fit.h), or a rig's every small misfit would
  // count as a change.
  const double inflation = std::sqrt(CorrelationInflation(robust.residual));
  const Eigen::VectorXd jackknife =
      JackknifeSigma(gram, cols, prior).tail(static_cast<Eigen::Index>(effect_cols.size()));
  int at = 0;
  for (Effect e : baseline) {
    fit.delta[e] = robust.theta.segment(at, ParameterCount(e));
    fit.sigma[e] =
        (inflation * robust.sigma.segment(at, ParameterCount(e))).cwiseMax(jackknife.segment(at, ParameterCount(e)));
    at += ParameterCount(e);
  }
  return fit;
}

// One term of a pair a group reads (a periodic error's amplitude and
// phase: the pair's sine and cosine terms, in the amplitude's unit).
struct PairTerm {
  ParameterGroup group;
  int leg = 0;  // 1–6 for a per-leg group
  bool cosine = false;
};

// The pair term θ index `t` is, if a group reads it in a pair.
std::optional<PairTerm> PairTermOf(Effect effect, int t) {
  for (const ParameterGroup& g : ParameterGroups(effect)) {
    if (calibration::HasSigma(g)) continue;
    for (int k = 0; k < calibration::ValueCount(g); ++k) {
      const int sine = calibration::ThetaIndex(g, k);
      if (t != sine && t != sine + 1) continue;
      const int leg = calibration::IsPerLeg(g) ? k / calibration::ValuesPerLeg(g) + 1 : 0;
      return PairTerm{g, leg, t == sine + 1};
    }
  }
  return std::nullopt;
}

// Every parameter of one effect, named by the vocabulary's groups; θ a
// group reads in pairs (a periodic error's amplitude and phase) as "theta",
// with its leg.
void Compare(const SavedEffect& e, const Eigen::VectorXd& delta, const Eigen::VectorXd& sigma_delta,
             std::vector<ParameterChange>* out) {
  const Eigen::VectorXd after = e.theta + delta;
  const auto sigma_of = [&](int t) { return std::hypot(sigma_delta(t), e.sigma(t)); };
  std::set<int> named;
  for (const ParameterGroup& g : ParameterGroups(e.effect)) {
    if (!calibration::HasSigma(g)) continue;
    for (int k = 0; k < calibration::ValueCount(g); ++k) {
      const int t = calibration::ThetaIndex(g, k);
      ParameterChange c;
      c.effect = e.effect;
      c.parameter = g.key;
      c.index = k;
      c.leg = calibration::IsPerLeg(g) ? k / calibration::ValuesPerLeg(g) + 1 : 0;
      c.before = calibration::GroupValue(g, e.theta.data(), k);
      c.after = calibration::GroupValue(g, after.data(), k);
      c.change = c.after - c.before;
      c.sigma = sigma_of(t);
      c.theta_index = t;
      out->push_back(c);
      named.insert(t);
    }
  }
  for (int t = 0; t < e.theta.size(); ++t) {
    if (named.count(t)) continue;
    ParameterChange c;
    c.effect = e.effect;
    c.parameter = "theta";
    c.index = c.theta_index = t;
    if (const std::optional<PairTerm> term = PairTermOf(e.effect, t)) c.leg = term->leg;
    c.before = e.theta(t);
    c.after = after(t);
    c.change = delta(t);
    c.sigma = sigma_of(t);
    out->push_back(c);
  }
  const std::vector<int> unapplied = calibration::UnappliedParameters(e.effect);
  for (ParameterChange& c : *out) {
    if (c.effect == e.effect)
      c.applied = std::find(unapplied.begin(), unapplied.end(), c.theta_index) == unapplied.end();
  }
}

}  // namespace

bool IsLegGeometry(Effect e) { return e == Effect::kLegOffset || e == Effect::kJointPosition; }

double ChangeThreshold(int tests, double chance) {
  const double p = chance / std::max(1, tests);
  double lo = 0.0, hi = 40.0;
  for (int k = 0; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return std::max(3.0, hi);
}

DriftReport Drift(const PlatformModel& model, const nlohmann::json& baseline, const std::string& origin,
                  const MeasurementData& data, const DriftOptions& options) {
  const DesignOptions o = SavedDesignOptions(baseline, origin);
  const std::vector<SavedEffect> effects =
      SavedAppliedEffects(AppliedModelJson(baseline, options.apply_ambiguous), o, origin);
  Design d = BuildDesign(model, Decimated(data, options.diagnose.max_rate_hz), o);
  DriftReport r;
  r.recorded_with_baseline = options.recorded_with_baseline;
  r.samples = d.samples();
  r.noise_floor_rms_m = NoiseFloorRms(d);
  const double sigma_axis = std::max(r.noise_floor_rms_m / std::sqrt(3.0), 1e-8);
  const TimeOffset clock = EstimateTimeOffset(d, PriorWeights(d, sigma_axis * sigma_axis));
  if (clock.applied) RemoveTimeOffset(clock.offset_s, &d);
  // Recorded without the baseline: apply it here. With it: what the
  // kinematics leaves out of a model is still in the data; take it out too.
  for (const SavedEffect& e : effects) {
    const ColumnRange& c = d.Of(e.effect);
    if (!options.recorded_with_baseline) {
      d.residual -= d.columns.middleCols(c.begin, c.count) * e.theta;
      continue;
    }
    for (int t : calibration::UnappliedParameters(e.effect)) d.residual -= d.columns.col(c.begin + t) * e.theta(t);
  }
  const RmsMax left = PointStats(WithoutFrame(d, d.residual), 0, d.samples());
  r.heldout_rms_m = left.rms_m;
  r.heldout_max_m = left.max_m;
  r.threshold_m = options.threshold_m > 0.0 ? options.threshold_m : 1.5 * r.noise_floor_rms_m;
  r.recalibrate = r.heldout_rms_m > r.threshold_m;

  std::vector<Effect> baseline_effects;
  for (const SavedEffect& e : effects) baseline_effects.push_back(e.effect);
  const Fitted fit = FitChange(d, baseline_effects, r.noise_floor_rms_m);
  for (const SavedEffect& e : effects) Compare(e, fit.delta.at(e.effect), fit.sigma.at(e.effect), &r.parameters);
  const int applied = static_cast<int>(
      std::count_if(r.parameters.begin(), r.parameters.end(), [](const ParameterChange& c) { return c.applied; }));
  r.z_threshold = ChangeThreshold(applied, (1.0 - kLegsShare) * kFamilyWiseChance);
  r.leg_z_threshold = ChangeThreshold(6, kLegsShare * kFamilyWiseChance);
  // Whether an effect is there at all, before and after, is another
  // question than whether it changed: one bar over the legs and the
  // applied parameters, the whole 5%.
  const double presence_z = ChangeThreshold(6 + applied, kFamilyWiseChance);
  const double samples = std::max(1, d.samples());
  for (ParameterChange& c : r.parameters) {
    c.z = c.sigma > 0.0 ? c.change / c.sigma : 0.0;
    const int column = d.Of(c.effect).begin + c.theta_index;
    c.at_a_m = std::abs(fit.delta.at(c.effect)(c.theta_index)) * d.columns.col(column).norm() / std::sqrt(samples);
    if (c.applied && std::abs(c.z) >= r.z_threshold && c.at_a_m >= kChangeAtAShare * r.noise_floor_rms_m) {
      r.changed.push_back(c);
    }
  }
  Columns changed_columns;
  for (const ParameterChange& c : r.changed) {
    if (!IsLegGeometry(c.effect)) changed_columns.push_back(d.Of(c.effect).begin + c.theta_index);
  }
  for (LegChange c : LegLengths(d, changed_columns, r.noise_floor_rms_m)) {
    c.z = c.sigma_m > 0.0 ? c.change_m / c.sigma_m : 0.0;
    c.at_a_m =
        std::abs(c.change_m) * d.columns.col(d.Of(Effect::kLegOffset).begin + c.leg - 1).norm() / std::sqrt(samples);
    r.legs.push_back(c);
    if (std::abs(c.z) >= r.leg_z_threshold && c.at_a_m >= kChangeAtAShare * r.noise_floor_rms_m) {
      r.legs_changed.push_back(c);
    }
  }
  for (const SavedEffect& e : effects) {
    bool was = false, is = false;
    for (int t = 0; t < e.theta.size(); ++t) {
      const double before = e.theta(t), after = before + fit.delta.at(e.effect)(t);
      was = was || (e.sigma(t) > 0.0 ? std::abs(before) >= presence_z * e.sigma(t) : before != 0.0);
      is = is || std::abs(after) >= presence_z * std::max(fit.sigma.at(e.effect)(t), 1e-300);
    }
    if (was && !is) r.vanished.push_back(e.effect);
  }
  // What the baseline does not hold and the data now names: the diagnosis
  // of the session (recorded with the baseline, of what it leaves).
  // Against every effect the baseline file names, applied or not: one it
  // names but does not apply was there when it was made.
  std::vector<Effect> named;
  for (const auto& entry : baseline["effects"]) {
    Effect e;
    if (entry.is_object() && ParseEffect(entry.value("name", ""), &e)) named.push_back(e);
  }
  DiagnoseOptions leaves = options.diagnose;
  leaves.against = Against::kCalibration;
  const Diagnosis now = Diagnose(model, data, leaves);
  for (const EffectResult& e : now.effects) {
    if (e.verdict == Verdict::kIdentified && !Contains(named, e.effect)) r.appeared.push_back(e.effect);
  }
  return r;
}

nlohmann::json ToJson(const DriftReport& r) {
  const auto entry = [](const ParameterChange& c) {
    nlohmann::json j = {{"effect", EffectName(c.effect)},
                        {"parameter", c.parameter},
                        {"index", c.index},
                        {"before", c.before},
                        {"after", c.after},
                        {"change", c.change},
                        {"sigma", c.sigma},
                        {"z", c.z},
                        {"at_a_m", c.at_a_m},
                        {"applied", c.applied}};
    if (c.leg > 0) j["leg"] = c.leg;
    return j;
  };
  const auto names = [](const std::vector<Effect>& effects) {
    std::vector<std::string> out;
    for (Effect e : effects) out.push_back(EffectName(e));
    return out;
  };
  const auto leg = [](const LegChange& c) {
    return nlohmann::json{
        {"leg", c.leg}, {"change_m", c.change_m}, {"sigma_m", c.sigma_m}, {"z", c.z}, {"at_a_m", c.at_a_m}};
  };
  nlohmann::json j;
  j["recorded_with_baseline"] = r.recorded_with_baseline;
  j["legs_changed"] = nlohmann::json::array();
  for (const LegChange& c : r.legs_changed) j["legs_changed"].push_back(leg(c));
  j["legs"] = nlohmann::json::array();
  for (const LegChange& c : r.legs) j["legs"].push_back(leg(c));
  j["samples"] = r.samples;
  j["changed"] = nlohmann::json::array();
  for (const ParameterChange& c : r.changed) j["changed"].push_back(entry(c));
  j["parameters"] = nlohmann::json::array();
  for (const ParameterChange& c : r.parameters) j["parameters"].push_back(entry(c));
  j["z_threshold"] = r.z_threshold;
  j["leg_z_threshold"] = r.leg_z_threshold;
  j["appeared"] = names(r.appeared);
  j["vanished"] = names(r.vanished);
  j["heldout_rms_m"] = r.heldout_rms_m;
  j["heldout_max_m"] = r.heldout_max_m;
  j["noise_floor_rms_m"] = r.noise_floor_rms_m;
  j["threshold_m"] = r.threshold_m;
  j["recalibrate"] = r.recalibrate;
  return j;
}

std::string ChangeText(const ParameterChange& c) {
  std::string unit = "", label = c.parameter;
  double scale = 1.0;
  int decimals = 6;
  for (const ParameterGroup& g : ParameterGroups(c.effect)) {
    if (c.parameter == g.key) unit = g.unit, label = g.label, scale = g.unit_scale, decimals = g.decimals;
  }
  int leg = c.leg;
  if (const std::optional<PairTerm> term = PairTermOf(c.effect, c.theta_index); c.parameter == "theta" && term) {
    const ParameterGroup& g = term->group;
    unit = g.unit, scale = g.unit_scale, decimals = g.decimals;
    label = fmt::format("{}, its {} term", g.label, term->cosine ? "cosine" : "sine");
    leg = term->leg;
  }
  const std::string where = leg > 0 ? fmt::format(" leg {}", leg) : "";
  return fmt::format("{} {}{}: {:.{}f} → {:.{}f} {}, {:+.{}f} ± {:.{}f} {} ({:.1f}σ)", EffectName(c.effect), label,
                     where, c.before * scale, decimals, c.after * scale, decimals, unit, c.change * scale, decimals,
                     c.sigma * scale, decimals, unit, std::abs(c.z));
}

std::string LegChangeText(const LegChange& c) {
  return fmt::format("leg {} length: {:+.1f} ± {:.1f} µm ({:.1f}σ)", c.leg, c.change_m * 1e6, c.sigma_m * 1e6,
                     std::abs(c.z));
}

std::string DriftText(const DriftReport& r) {
  std::string text;
  for (const LegChange& c : r.legs_changed) text += LegChangeText(c) + "\n";
  for (const ParameterChange& c : r.changed) text += ChangeText(c) + "\n";
  if (r.changed.empty() && r.legs_changed.empty()) {
    text += fmt::format("no leg's length changed beyond {:.1f}σ and no parameter beyond {:.1f}σ\n", r.leg_z_threshold,
                        r.z_threshold);
  }
  const auto list = [](const std::vector<Effect>& effects) {
    std::string s;
    for (Effect e : effects) s += (s.empty() ? "" : ", ") + std::string(EffectName(e));
    return s.empty() ? std::string("none") : s;
  };
  text += fmt::format("appeared: {}; vanished: {}\n", list(r.appeared), list(r.vanished));
  text += fmt::format(
      "the baseline leaves {:.1f} µm RMS ({:.1f} max) on this data, noise floor {:.1f} µm; "
      "threshold {:.1f} µm: {}\n",
      r.heldout_rms_m * 1e6, r.heldout_max_m * 1e6, r.noise_floor_rms_m * 1e6, r.threshold_m * 1e6,
      r.recalibrate ? "recalibrate" : "no need to recalibrate");
  return text;
}

}  // namespace edsp::gap
