#include "edsp/diagnosis/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/gnuplot.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/parameter_table.h"
#include "edsp/diagnosis/saved_model.h"
#include "edsp/kinematics/calibration.h"

namespace edsp::gap {

namespace {

nlohmann::json StatsJson(const RmsMax& s) { return {{"rms_m", s.rms_m}, {"max_m", s.max_m}}; }

// The tracker's clock (a nuisance, never an effect; time_offset.h).
nlohmann::json TimeOffsetJson(const TimeOffset& t) {
  nlohmann::json j = {{"estimated", t.estimated}, {"applied", t.applied}, {"note", t.note}};
  if (t.estimated) {
    j["offset_s"] = t.offset_s;
    j["sigma_s"] = t.sigma_s;
  }
  return j;
}

nlohmann::json EffectJson(const EffectResult& r) {
  nlohmann::json j;
  j["name"] = EffectName(r.effect);
  j["params"] = r.theta.size() ? ParametersJson(r.effect, r.theta.data()) : nlohmann::json::object();
  const auto groups = ParameterGroups(r.effect);
  // An effect none of whose values has a σ of its own (amplitude, phase) gets no "sigma".
  if (std::any_of(groups.begin(), groups.end(), calibration::HasSigma)) {
    j["sigma"] = r.sigma.size() ? SigmaJson(r.effect, r.sigma.data()) : nlohmann::json::object();
  }
  j["explained_fraction"] = r.explained_fraction;
  j["cv_gain"] = r.cv_gain;
  j["verdict"] = VerdictName(r.verdict);
  j["frame_overlap"] = r.frame_overlap;
  if (!r.correlated_with.empty()) {
    j["max_correlation"] = r.max_correlation;
    j["correlated_with"] = r.correlated_with;
  }
  if (const std::vector<std::string> with = AmbiguousWithNames(r); !with.empty()) j["ambiguous_with"] = with;
  if (r.encoder_checked) j["encoder_share_of_lag"] = r.encoder_share;
  if (!r.next_measurement.empty()) j["next_measurement"] = r.next_measurement;
  return j;
}

// The PR compensation to run next, when passive_rotation was selected: the
// screws' fitted PR as a scale of the signed model where it is one.
nlohmann::json Compensation(const Diagnosis& d) {
  for (const EffectResult& r : d.effects) {
    if (r.effect != Effect::kPassiveRotation || r.verdict == Verdict::kRejected || r.theta.size() != 2) continue;
    const double scale = r.theta(0) + (1.0 + r.theta(1)) * d.applied_pr_ratio;
    nlohmann::json c = {{"pr_mode", "signed"},
                        {"pr_scale", scale},
                        {"applied", AppliedPrName(d.applied_pr)},
                        {"applied_ratio_to_signed", d.applied_pr_ratio}};
    c["note"] = fmt::format(
        "the screws follow {:.3f} × the signed PR model (pr_sign × lead relative to the config); "
        "the data's controller applied '{}' compensation: run PR mode signed{}",
        scale, AppliedPrName(d.applied_pr),
        std::abs(scale - 1.0) > 0.02 ? fmt::format(" with pr_sign·lead scaled by {:.3f}", scale) : "");
    return c;
  }
  return {{"pr_mode", d.applied_pr ? PrModeName(*d.applied_pr) : "unchanged"}, {"note", "no PR change indicated"}};
}

// Without encoders: whether the servo_lag found is one a clock offset
// makes. The offset is the one that would stand in for the lag, which is
// the clock's only when it does as well.
std::string ClockOffsetNote(const ClockOffsetCheck& c) {
  if (!c.tested) return "";
  return fmt::format(
      "; the selected servo_lag {} a clock {} (the offset that would stand in for it) on the "
      "held-out runs{}",
      c.replaces_lag ? "predicts no better than" : "beats", ClockAhead(c.offset_s, c.sigma_s),
      c.replaces_lag ? "" : ", though its velocity term may hold a clock offset beside the drives' lag");
}

}  // namespace

std::string TrackerClockNote(const Diagnosis& d) {
  const ClockDriftCheck& c = d.clock_drift;
  const std::string offset = d.time_offset.note + ClockOffsetNote(d.clock_offset);
  if (!c.tested) return offset;
  return offset + fmt::format("; over the session it drifts {:+.3f} ppm ± {:.3f} ({}: the held-out runs {} with it)",
                              c.drift * 1e6, c.sigma * 1e6,
                              c.drifts       ? "beyond the vocabulary"
                              : c.run_by_run ? "shown, but too small to matter"
                                             : "not shown run by run",
                              HeldOutChange(c.cv_gain));
}

namespace {

// Nothing beyond the noise, as an entry of the ranking.
nlohmann::json NoneJson(const RankedEntry& none) {
  return {{"name", RankedName(none)},
          {"verdict", VerdictName(RankedVerdict(none))},
          {"explained_fraction", 0.0},
          {"params", nlohmann::json::object()}};
}

// Structure no effect explains, as an entry of the ranking: its share of the
// gap's variance (the held-out residual's part above its white level).
nlohmann::json UnknownJson(const Diagnosis& d, const RankedEntry& unknown) {
  const double left = d.structure.structured_rms_m * d.structure.structured_rms_m;
  const double gap = std::max(1e-30, d.gap.overall.rms_m * d.gap.overall.rms_m);
  return {{"name", RankedName(unknown)},        {"verdict", VerdictName(RankedVerdict(unknown))},
          {"params", nlohmann::json::object()}, {"explained_fraction", 0.0},
          {"unexplained_fraction", left / gap}, {"note", d.unexplained_note}};
}

nlohmann::json StructureJson(const ResidualStructure& s) {
  return {{"structured", s.structured},
          {"share_above_white", s.structured_share},
          {"rms_m", s.structured_rms_m},
          {"ljung_box_q", s.whiteness.q},
          {"threshold_99", s.whiteness.threshold},
          {"dominant_hz", s.dominant_hz},
          {"damping", s.damping},
          {"follows", s.follows},
          {"follows_r2", s.follows_r2},
          {"largest_in", s.largest_in},
          {"in_sample_share_above_white", s.in_sample_share},
          {"in_sample_ljung_box_q", s.in_sample_whiteness.q},
          {"runs_apart", s.runs_apart},
          {"run_offset_share", s.run_offset_share},
          {"in_sample_run_offset_share", s.in_sample_run_offset_share},
          {"note", s.Describe()}};
}

// What a calibration applies and how well it predicts the held-out runs.
nlohmann::json CalibrationJson(const CalibrationResult& c) {
  std::vector<std::string> names;
  for (Effect e : c.effects) names.push_back(EffectName(e));
  return {{"effects", names},
          {"chosen_by", ChosenByName(c.chosen_by)},
          {"heldout_rms_m", c.heldout_rms_m},
          {"identified_heldout_rms_m", c.identified_heldout_rms_m}};
}

}  // namespace

std::string RecordedCorrectionText(const Diagnosis& d) {
  if (d.recorded_correction_rms_m <= 0.0) return "";
  if (d.against == Against::kNominal) {
    return fmt::format(
        "recorded with a calibration in force (it moved point A by {:.1f} µm RMS): diagnosed against "
        "the nominal model, its correction taken back out, so the effects are the rig's whole and a "
        "model saved replaces that calibration",
        d.recorded_correction_rms_m * 1e6);
  }
  return fmt::format(
      "recorded with a calibration in force (it moved point A by {:.1f} µm RMS): diagnosed against "
      "it, so the effects are what it leaves, not the rig's whole",
      d.recorded_correction_rms_m * 1e6);
}

std::vector<RankedEntry> Ranking(const Diagnosis& d) {
  std::vector<RankedEntry> ranking;
  const bool unknown = NamesUnknown(d.conclusion);
  if (d.conclusion == Conclusion::kNone) ranking.push_back({RankedEntry::Kind::kNone});
  if (unknown && d.selected.empty()) ranking.push_back({RankedEntry::Kind::kUnknown});
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    ranking.push_back({RankedEntry::Kind::kEffect, &d.effects[k]});
    if (unknown && k + 1 == d.selected.size()) ranking.push_back({RankedEntry::Kind::kUnknown});
  }
  return ranking;
}

// The pseudo-effects are named as the conclusions they make (conclusion.h).
std::string RankedName(const RankedEntry& e) {
  if (e.kind == RankedEntry::Kind::kNone) return ConclusionName(Conclusion::kNone);
  if (e.kind == RankedEntry::Kind::kUnknown) return ConclusionName(Conclusion::kUnknown);
  return EffectName(e.result->effect);
}

Verdict RankedVerdict(const RankedEntry& e) {
  return e.kind == RankedEntry::Kind::kEffect ? e.result->verdict : Verdict::kIdentified;
}

namespace {

nlohmann::json RankedJson(const Diagnosis& d, const RankedEntry& e) {
  if (e.kind == RankedEntry::Kind::kNone) return NoneJson(e);
  if (e.kind == RankedEntry::Kind::kUnknown) return UnknownJson(d, e);
  nlohmann::json j = EffectJson(*e.result);
  if (e.result->effect == Effect::kStructuralResonance && d.design.structural_mode_hz > 0.0) {
    j["params"]["frequency_hz"] = d.design.structural_mode_hz;  // chosen, not fitted:
    j["params"]["damping"] = d.design.structural_mode_damping;  // no σ
  }
  return j;
}

// A change of the rig within the session (change_point.h): the fields of
// interfaces.md §4's `events`, then the evidence.
nlohmann::json EventJson(const ChangeEvent& e) {
  nlohmann::json j = {{"time_s", e.time_s},
                      {"after_s", e.after_s},
                      {"run", e.run},
                      {"kind", ChangeKindName(e.kind)},
                      {"leg", e.kind == ChangeKind::kLegLength ? nlohmann::json(e.leg + 1) : nlohmann::json(nullptr)}};
  if (e.kind == ChangeKind::kLegLength) {
    j["parameter"] = "length_m";
    j["size"] = e.size(0);
    j["sigma"] = e.sigma(0);
  } else {
    const Vector3 t = e.size.head<3>(), w = e.size.tail<3>();
    j["parameter"] = "translation_m";
    j["size"] = t.norm();
    j["sigma"] = e.sigma.head<3>().norm();
    j["translation_m"] = {t.x(), t.y(), t.z()};
    j["rotation_rad"] = {w.x(), w.y(), w.z()};
    j["sigma_translation_m"] = {e.sigma(0), e.sigma(1), e.sigma(2)};
    j["sigma_rotation_rad"] = {e.sigma(3), e.sigma(4), e.sigma(5)};
  }
  j["evidence"] = {{"wald", e.wald},
                   {"threshold", e.threshold},
                   {"variance_inflation", e.inflation},
                   {"step_sigma2", e.step_sigma2},
                   {"drift_sigma2", e.drift_sigma2},
                   {"drift", e.drift},
                   {"left_sigma2", e.left_sigma2},
                   {"left_threshold", e.left_threshold}};
  if (e.alternative != StepRejection::kNone) j["alternative"] = StepRejectionName(e.alternative);
  return j;
}

nlohmann::json EventsJson(const std::vector<ChangeEvent>& events) {
  nlohmann::json j = nlohmann::json::array();
  for (const ChangeEvent& e : events) j.push_back(EventJson(e));
  return j;
}

// Why a significant step is no event, with its evidence.
std::string WhyRejected(const ChangeEvent& e) {
  switch (e.alternative) {
    case StepRejection::kStructure:
      return fmt::format(
          "its signature varies block by block beyond it ({:.0f} σ² left against {:.0f}), structure rather than "
          "one change",
          e.left_sigma2, e.left_threshold);
    case StepRejection::kDrift:
      return fmt::format("a drift ({}) explains it as well ({:.0f} σ² against {:.0f})", e.drift, e.drift_sigma2,
                         e.step_sigma2);
    case StepRejection::kUndetermined: return "the session cannot size it (past 1 mm or 1 mrad in some direction)";
    case StepRejection::kOtherSignature:
      return "a better step of another signature, turned away, stands at its instant";
    case StepRejection::kNone: break;
  }
  return "";
}

}  // namespace

std::string ChangesText(const Diagnosis& d) {
  if (!d.changes.searched) return "not searched";
  std::string text;
  for (const ChangeEvent& e : d.changes.events) text += (text.empty() ? "" : "; ") + DescribeEvent(e);
  if (text.empty())
    text = "none: one rig explains the whole session";
  else
    text += "; the diagnosis is of the rig after the last change";
  for (const ChangeEvent& e : d.changes.rejected)
    text += "; a step " + DescribeEvent(e) + " was rejected: " + WhyRejected(e);
  return text;
}

nlohmann::json ToJson(const Diagnosis& d) {
  nlohmann::json j;
  j["gap"] = ToJson(d.gap);
  j["effects"] = nlohmann::json::array();
  for (const RankedEntry& e : Ranking(d)) j["effects"].push_back(RankedJson(d, e));
  j["selected"] = nlohmann::json::array();
  for (Effect e : d.selected) j["selected"].push_back(EffectName(e));
  j["events"] = EventsJson(d.changes.events);
  j["change_search"] = {{"searched", d.changes.searched},
                        {"rejected", EventsJson(d.changes.rejected)},
                        {"blocks", d.changes.blocks},
                        {"candidates", d.changes.candidates},
                        {"structural_mode_hz", d.changes.structural_mode_hz}};
  j["conclusion"] = ConclusionName(d.conclusion);
  j["calibration"] = CalibrationJson(d.calibration);
  j["holdout"] = {{"runs", d.holdout_runs},
                  {"before", StatsJson(d.holdout_before)},
                  {"after", StatsJson(d.holdout_after)},
                  {"shrink", d.shrink},
                  {"gap_shrink", d.gap_shrink}};
  j["unexplained"] = {{"rms_m", d.unexplained.rms_m},
                      {"max_m", d.unexplained.max_m},
                      {"note", d.unexplained_note},
                      {"noise_floor_rms_m", d.noise_floor_rms_m},
                      {"whiteness",
                       {{"white", d.whiteness.white},
                        {"ljung_box_q", d.whiteness.q},
                        {"dof", d.whiteness.dof},
                        {"threshold_99", d.whiteness.threshold},
                        {"lag1_autocorrelation", d.whiteness.lag1},
                        {"outside_99_band", d.whiteness.outside_fraction}}},
                      {"structure", StructureJson(d.structure)},
                      {"base_tilt",
                       {{"tested", d.base_tilt.tested},
                        {"cv_gain", d.base_tilt.cv_gain},
                        {"tilts", d.base_tilt.tilts},
                        {"in_place_cv_gain", d.base_tilt.in_place_cv_gain},
                        {"in_place_share", d.base_tilt.in_place_share},
                        {"replaces", d.base_tilt.replaces}}},
                      {"clock_drift",
                       {{"tested", d.clock_drift.tested},
                        {"drift", d.clock_drift.drift},
                        {"sigma", d.clock_drift.sigma},
                        {"cv_gain", d.clock_drift.cv_gain},
                        {"run_by_run", d.clock_drift.run_by_run},
                        {"drifts", d.clock_drift.drifts}}},
                      {"clock_offset",
                       {{"tested", d.clock_offset.tested},
                        {"offset_s", d.clock_offset.offset_s},
                        {"sigma_s", d.clock_offset.sigma_s},
                        {"replaces_lag", d.clock_offset.replaces_lag}}}};
  j["compensation"] = Compensation(d);
  // The tracker frame (a nuisance, never an effect): point_T = R·A_B + t.
  Matrix3 R = d.R0;
  Vector3 t = d.t0;
  if (d.frame.size() == 6) {
    const Vector3 w = d.frame.tail<3>();
    if (w.norm() > 0.0) R = d.R0 * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    t = d.t0 + d.frame.head<3>();
  }
  const Eigen::Quaterniond q(R);
  j["tracker_frame"] = {{"translation_m", {t.x(), t.y(), t.z()}}, {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  j["time_offset"] = TimeOffsetJson(d.time_offset);
  j["fit"] = {{"solver", "ceres"},
              {"loss", "huber"},
              {"huber_m", d.robust.huber_m},
              {"iterations", d.robust.iterations},
              {"converged", d.robust.converged},
              {"covariance", d.robust.covariance_ok},
              {"cross_validation", "leave one run out"},
              {"condition_number",
               std::isfinite(d.condition_number) ? nlohmann::json(d.condition_number) : nlohmann::json("inf")}};
  j["samples"] = d.samples;
  j["timing_excluded_samples"] = d.timing_excluded;
  if (d.has_encoder) {
    j["drives"] = {{"described_rms_m", d.drives_described_rms_m},
                   {"rest_rms_m", d.drives_rest_rms_m},
                   {"rest_taken_out", d.drives_rest_taken_out}};
  }
  j["recorded_correction"] = {{"against", AgainstName(d.against)}, {"rms_m", d.recorded_correction_rms_m}};
  j["seconds"] = d.seconds;
  return j;
}

namespace {

// The tracker's rotation with the fit's own small correction to it.
Matrix3 FittedTrackerRotation(const Diagnosis& d) {
  if (d.frame.size() < 6) return d.R0;
  const Vector3 w = d.frame.segment<3>(3);
  if (!(w.norm() > 0.0)) return d.R0;
  return d.R0 * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
}

// The residual once the prediction (tracker frame, around the data's R0) is
// taken off. Where the data cannot fix the frame's rotation
// (FixesFrameRotation), R0 is arbitrary about some axis and would turn the
// prediction with it: then the fit's rotation turns it, if the model has it.
Eigen::VectorXd ResidualAfterPrediction(const Design& d, const Eigen::VectorXd& predicted,
                                        const std::optional<Matrix3>& fit_rotation) {
  if (!fit_rotation || predicted.isZero(0.0) || FixesFrameRotation(d.model_point)) return d.residual - predicted;
  Eigen::VectorXd predicted_B(predicted.size());
  for (Eigen::Index row = 0; row + 2 < predicted.size(); row += 3) {
    predicted_B.segment<3>(row) = d.R0.transpose() * predicted.segment<3>(row);
  }
  return ResidualInFrame(d, *fit_rotation, predicted_B);
}

}  // namespace

nlohmann::json ModelJson(const Diagnosis& d) {
  nlohmann::json j;
  j["format"] = "edsp-gap-model/1";
  if (!d.platform.empty()) j["platform"] = d.platform;  // a calibration refuses another platform
  j["thermal_time_constant_s"] = d.design.thermal_time_constant_s;
  j["backlash_width_m"] = d.design.backlash_width_m;
  // The tracker's frame is the data's nuisance; its rotation is kept for
  // data that cannot fix it (Evaluate).
  j["tracker_rotation"] = TrackerRotationJson(FittedTrackerRotation(d));
  if (d.design.structural_mode_hz > 0.0) {
    j["structural_mode_hz"] = d.design.structural_mode_hz;
    j["structural_mode_damping"] = d.design.structural_mode_damping;
  }
  // The calibration's effects, applied; then the named effects it leaves
  // out, with their own fit, applied only if asked (--apply-ambiguous).
  j["effects"] = nlohmann::json::array();
  const auto verdict = [&](Effect e) {
    for (const EffectResult& r : d.effects) {
      if (r.effect == e) return r.verdict;
    }
    return Verdict::kRejected;
  };
  const CalibrationResult& c = d.calibration;
  const auto values = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  for (std::size_t k = 0; k < c.effects.size(); ++k) {
    j["effects"].push_back({{"name", EffectName(c.effects[k])},
                            {"verdict", VerdictName(verdict(c.effects[k]))},
                            {"theta", values(c.theta[k])},
                            {"sigma", values(c.sigma[k])},
                            {"apply", true}});
  }
  for (const EffectResult& r : d.effects) {
    const bool selected = std::find(d.selected.begin(), d.selected.end(), r.effect) != d.selected.end();
    const bool calibrated = std::find(c.effects.begin(), c.effects.end(), r.effect) != c.effects.end();
    if (r.verdict == Verdict::kRejected || !selected || calibrated) continue;
    j["effects"].push_back({{"name", EffectName(r.effect)},
                            {"verdict", VerdictName(r.verdict)},
                            {"theta", values(r.theta)},
                            {"sigma", values(r.sigma)},
                            {"apply", false}});
  }
  j["calibration"] = CalibrationJson(c);
  return j;
}

namespace {

// A saved entry's verdict as the kinematics' rule reads it (AppliesEntry):
// none, or not a name, is identified, as in a file saved before verdicts;
// a name that is no verdict is applied only as its "apply" says, as a
// rejected one is. Lenient where the kinematics refuses the file: this only
// keeps the part of a model that would be applied.
Verdict EntryVerdict(const nlohmann::json& e) {
  if (!e.contains("verdict") || !e["verdict"].is_string()) return Verdict::kIdentified;
  return VerdictFromName(e["verdict"].get<std::string>()).value_or(Verdict::kRejected);
}

}  // namespace

nlohmann::json EmptyModelJson() { return {{"format", "edsp-gap-model/1"}, {"effects", nlohmann::json::array()}}; }

nlohmann::json AppliedModelJson(const nlohmann::json& saved, bool apply_ambiguous) {
  nlohmann::json applied = saved;
  if (!saved.is_object() || !saved.contains("effects") || !saved["effects"].is_array()) return applied;
  applied["effects"] = nlohmann::json::array();
  for (const auto& e : saved["effects"]) {
    if (!e.is_object()) continue;
    const bool has_apply = e.contains("apply") && e["apply"].is_boolean();
    if (calibration::AppliesEntry(EntryVerdict(e), has_apply, has_apply && e["apply"].get<bool>(), apply_ambiguous)) {
      applied["effects"].push_back(e);
      applied["effects"].back()["apply"] = true;  // what it holds is applied, whatever the file said
    }
  }
  return applied;
}

Evaluation Evaluate(const PlatformModel& model, const MeasurementData& data, const nlohmann::json& saved,
                    const std::string& origin) {
  const DesignOptions o = SavedDesignOptions(saved, origin);
  const std::vector<SavedEffect> effects = SavedAppliedEffects(saved, o, origin);
  // A model applied to data recorded with a calibration in force takes that
  // calibration's place, as in the kinematics: the data read as the nominal
  // model commanded it. With no model, the error as measured.
  const bool replaces = !effects.empty() && CarriesACorrection(data);
  Design d = BuildDesign(model, Decimated(replaces ? AsCommandedNominally(model, data) : data, 100.0), o);
  // The tracker's clock is the data's nuisance, as its frame is: estimated
  // on this data, never carried over from the model.
  const double sigma_axis = std::max(NoiseFloorRms(d) / std::sqrt(3.0), 1e-8);
  const TimeOffset clock = EstimateTimeOffset(d, PriorWeights(d, sigma_axis * sigma_axis));
  if (clock.applied) RemoveTimeOffset(clock.offset_s, &d);
  Eigen::VectorXd predicted = Eigen::VectorXd::Zero(d.residual.size());
  for (const SavedEffect& e : effects) {
    const ColumnRange& r = d.Of(e.effect);
    predicted += d.columns.middleCols(r.begin, r.count) * e.theta;
  }
  // Frame alone, before and after: only the effects are carried over.
  auto frame_fit = [&](const Eigen::VectorXd& r) {
    const auto F = d.columns.leftCols(6);
    const Eigen::VectorXd x = (F.transpose() * F).ldlt().solve(F.transpose() * r);
    return Eigen::VectorXd(r - F * x);
  };
  Evaluation ev;
  ev.against_nominal = replaces;
  ev.samples = d.samples();
  ev.timing_excluded = data.timing_excluded;
  const std::int64_t all_rows = data.timing_excluded + static_cast<std::int64_t>(data.rows.size());
  ev.timing_excluded_share =
      all_rows > 0 ? static_cast<double>(data.timing_excluded) / static_cast<double>(all_rows) : 0.0;
  ev.timing_kept = data.timing_kept;
  ev.timing_kept_share = all_rows > 0 ? static_cast<double>(data.timing_kept) / static_cast<double>(all_rows) : 0.0;
  const Eigen::VectorXd before = frame_fit(d.residual);
  const Eigen::VectorXd after = frame_fit(ResidualAfterPrediction(d, predicted, SavedTrackerRotation(saved, origin)));
  ev.before = PointStats(before, 0, d.samples());
  ev.after = PointStats(after, 0, d.samples());
  ev.shrink = Shrink(ev.before.rms_m, ev.after.rms_m);
  for (std::size_t k = 0; k < d.runs.size(); ++k) {
    const ColumnRange& samples = d.run_samples[k];
    ev.by_run.push_back(
        {d.runs[k], PointStats(before, samples.begin, samples.count), PointStats(after, samples.begin, samples.count)});
  }
  ev.noise_floor_rms_m = NoiseFloorRms(d);
  ev.gap_shrink = GapShrink(ev.before.rms_m, ev.after.rms_m, ev.noise_floor_rms_m);
  ev.time_offset = clock;
  return ev;
}

nlohmann::json ToJson(const Evaluation& e) {
  nlohmann::json by_run = nlohmann::json::array();
  for (const RunEvaluation& r : e.by_run) {
    by_run.push_back({{"run", r.run}, {"before", StatsJson(r.before)}, {"after", StatsJson(r.after)}});
  }
  return {{"before", StatsJson(e.before)},
          {"after", StatsJson(e.after)},
          {"shrink", e.shrink},
          {"gap_shrink", e.gap_shrink},
          {"samples", e.samples},
          {"timing_excluded_samples", e.timing_excluded},
          {"timing_excluded_share", e.timing_excluded_share},
          {"by_run", by_run},
          {"noise_floor_rms_m", e.noise_floor_rms_m},
          {"time_offset", TimeOffsetJson(e.time_offset)},
          {"recorded_correction", {{"against", e.against_nominal ? "nominal" : "calibration"}}}};
}

namespace {

// The verdict: the conclusion, the ranking and what held-out runs say.
std::string VerdictMarkdown(const Diagnosis& d) {
  std::string md = "## Verdict\n\n";
  const std::string conclusion = ConclusionName(d.conclusion);
  if (d.conclusion == Conclusion::kNone)
    md += "**" + conclusion + "**: the measurement agrees with the model within the tracker's noise.\n\n";
  else if (NamesUnknown(d.conclusion))
    md += "**" + conclusion + "**: " + d.unexplained_note + ".\n\n";
  else
    md += "**" + conclusion + "**\n\n";
  md +=
      "| rank | effect | verdict | explained | held-out gain | with | next measurement "
      "|\n|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    const EffectResult& r = d.effects[k];
    md += fmt::format("| {} | `{}` | {} | {} | {} | {} | {} |\n", k + 1, EffectName(r.effect), VerdictName(r.verdict),
                      Percent(r.explained_fraction), Percent(r.cv_gain), fmt::join(AmbiguousWithNames(r), ", "),
                      r.next_measurement);
  }
  md += fmt::format(
      "\nOn runs held out of every fit: {:.1f} µm RMS ({:.1f} max) before, {:.1f} µm RMS ({:.1f} max) "
      "after the selected effects, shrink {:.0f}%; the tracker's noise floor is {:.1f} µm, {}.\n\n",
      d.holdout_before.rms_m * 1e6, d.holdout_before.max_m * 1e6, d.holdout_after.rms_m * 1e6,
      d.holdout_after.max_m * 1e6, 100 * d.shrink, d.noise_floor_rms_m * 1e6,
      GapShrinkText(d.holdout_before.rms_m, d.noise_floor_rms_m, d.gap_shrink));
  return md;
}

std::string ParametersMarkdown(const Diagnosis& d) {
  std::string md = "## Parameters of the effects found\n\nEach value ± its 1-σ from the Ceres fit.\n\n";
  bool any = false;
  for (const EffectResult& r : d.effects) {
    if (r.verdict == Verdict::kRejected || r.theta.size() == 0) continue;
    any = true;
    md += ParameterTableMarkdown(r);
    if (r.effect == Effect::kStructuralResonance && d.design.structural_mode_hz > 0.0) {
      md += fmt::format("| mode frequency (the held-out runs' best) | {:.3f} | Hz |\n| damping ratio ζ | {:.3f} | |\n",
                        d.design.structural_mode_hz, d.design.structural_mode_damping);
    }
    if (!r.correlated_with.empty()) {
      md += fmt::format("\nStrongest correlation of a parameter: {:.2f}, with {}.\n", r.max_correlation,
                        r.correlated_with);
    }
    md += "\n";
  }
  if (!any) md += "None.\n\n";
  return md;
}

std::string WhereMarkdown(const Diagnosis& d) {
  std::string md = "## Where the gap lies\n\n" + d.gap.where + "\n\n";
  md += fmt::format("Before any effect: {:.1f} µm RMS, {:.1f} µm max at A.\n\n", d.gap.overall.rms_m * 1e6,
                    d.gap.overall.max_m * 1e6);
  md += "| run | RMS (µm) | max (µm) |\n|---|---|---|\n";
  for (const auto& [run, s] : d.gap.by_run)
    md += fmt::format("| {} | {:.1f} | {:.1f} |\n", run, s.rms_m * 1e6, s.max_m * 1e6);
  md +=
      "\n![gap against time](gap_vs_time.png)\n\n![gap against displacement](gap_vs_displacement.png)\n\n"
      "![legs](legs.png)\n\n![after the selected effects](after_vs_time.png)\n\n";
  return md;
}

// What a rig team does with the result: apply, measure, or look further.
std::string NextStepsMarkdown(const Diagnosis& d) {
  std::string md = "## What to do next\n\n";
  std::vector<std::string> apply, measure;
  for (const EffectResult& r : d.effects) {
    const bool selected = std::find(d.selected.begin(), d.selected.end(), r.effect) != d.selected.end();
    if (selected && r.verdict == Verdict::kIdentified) apply.push_back(fmt::format("`{}`", EffectName(r.effect)));
    if (r.verdict == Verdict::kAmbiguous && !r.next_measurement.empty()) {
      measure.push_back(fmt::format("- `{}` (ambiguous with {}): {}", EffectName(r.effect),
                                    fmt::join(AmbiguousWithNames(r), ", "), r.next_measurement));
    }
  }
  if (!apply.empty()) {
    md += fmt::format(
        "- Apply {}: save the model (`edsp-gap diagnose … --save-model MODEL`) and run "
        "`edsp-kinematics --calibration MODEL` (or `[calibration] model` in the config).\n",
        fmt::join(apply, ", "));
  }
  md += "- PR compensation: " + Compensation(d)["note"].get<std::string>() + ".\n";
  md += "- Tracker clock: " + TrackerClockNote(d) + ".\n";
  if (!measure.empty())
    md += "- Separate the ambiguous effects with one more measurement:\n" +
          fmt::format("  {}\n", fmt::join(measure, "\n  "));
  if (NamesUnknown(d.conclusion))
    md += "- Look beyond the vocabulary: " + d.unexplained_note + ".\n";
  else
    md += "- What is left: " + d.unexplained_note + ".\n";
  return md;
}

}  // namespace

std::string ReportMarkdown(const Diagnosis& d) {
  std::string md = "# Gap diagnosis\n\n";
  md += fmt::format("{} samples in {} runs ({}), diagnosed in {:.1f} s.\n\n", d.samples, d.runs.size(),
                    fmt::join(d.runs, ", "), d.seconds);
  if (d.timing_excluded > 0) {
    md += fmt::format(
        "{} samples left out: the data flags them `timing_event` (near a stall of its real-time system, "
        "a transient no effect models).\n\n",
        d.timing_excluded);
  }
  if (const std::string recorded = RecordedCorrectionText(d); !recorded.empty()) md += "Data " + recorded + ".\n\n";
  md += fmt::format("Changes of the rig within the session (searched in {:.1f} s): {}.\n\n", d.changes.seconds,
                    ChangesText(d));
  return md + VerdictMarkdown(d) + ParametersMarkdown(d) + WhereMarkdown(d) + NextStepsMarkdown(d);
}

std::vector<std::string> WriteReport(const Diagnosis& d, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> files;
  // Per run: time, displacement, gap before and after (µm).
  std::ofstream data(dir + "/gap.dat");
  for (std::size_t run = 0; run < d.runs.size(); ++run) {
    data << "# run " << d.runs[run] << "\n";
    for (const SampleGap& s : d.series) {
      if (s.run == static_cast<int>(run)) {
        data << s.time_s << " " << s.displacement << " " << s.before_m * 1e6 << " " << s.after_m * 1e6 << "\n";
      }
    }
    data << "\n\n";
  }
  data.close();
  std::ofstream legs(dir + "/legs.dat");
  for (int i = 0; i < 6; ++i) {
    legs << i + 1 << " " << d.gap.by_leg_m[static_cast<std::size_t>(i)] * 1e6 << " "
         << d.gap.extending_mean_m[static_cast<std::size_t>(i)] * 1e6 << " "
         << d.gap.retracting_mean_m[static_cast<std::size_t>(i)] * 1e6 << "\n";
  }
  legs.close();
  auto per_run = [&](const std::string& x, int column) {
    std::string t;
    for (std::size_t k = 0; k < d.runs.size(); ++k) {
      t += fmt::format("{}'{}/gap.dat' index {} using {}:{} with {} title '{}'", k ? ", " : "", dir, k, x, column,
                       x == "1" ? "lines" : "points pt 7 ps 0.3", d.runs[k]);
    }
    return t;
  };
  GnuplotPng(
      dir, "gap_vs_time.png",
      "set xlabel 'time (s)'\nset ylabel '|gap at A| (µm)'\nset title 'Gap against time, before any effect'\nplot " +
          per_run("1", 3) + "\n");
  GnuplotPng(dir, "gap_vs_displacement.png",
             "set xlabel 'displacement from home (m + rad)'\nset ylabel '|gap at A| (µm)'\nset title 'Gap against "
             "displacement, before any effect'\nplot " +
                 per_run("2", 3) + "\n");
  GnuplotPng(dir, "after_vs_time.png",
             "set xlabel 'time (s)'\nset ylabel '|residual at A| (µm)'\nset title 'After the selected effects'\nplot " +
                 per_run("1", 4) + "\n");
  GnuplotPng(dir, "legs.png",
             fmt::format("set style data histograms\nset style fill solid 0.6\nset xlabel 'leg'\nset ylabel 'µm'\n"
                         "set title 'Leg-space gap: RMS, and mean while extending / retracting'\n"
                         "plot '{0}/legs.dat' using 2:xtic(1) title 'RMS', '' using 3 title 'extending mean', '' using "
                         "4 title 'retracting mean'\n",
                         dir));
  for (const char* png : {"gap_vs_time.png", "gap_vs_displacement.png", "after_vs_time.png", "legs.png"}) {
    if (std::filesystem::exists(dir + "/" + png)) files.push_back(dir + "/" + png);
  }

  std::ofstream md(dir + "/report.md");
  md << ReportMarkdown(d);
  files.push_back(dir + "/report.md");
  return files;
}

}  // namespace edsp::gap
