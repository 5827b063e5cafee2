#include "edsp/diagnosis/beyond_vocabulary.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "edsp/diagnosis/encoder_check.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/paired_test.h"
#include "edsp/diagnosis/percent_text.h"
#include "edsp/diagnosis/residual_structure.h"
#include "edsp/diagnosis/structure_nuisance.h"
#include "edsp/diagnosis/time_offset.h"

namespace edsp::gap {

namespace {

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

// The selected effects a base tilt resembles, and the rest.
std::pair<std::vector<Effect>, std::vector<Effect>> SplitByTiltLikeness(const std::vector<Effect>& selected) {
  std::pair<std::vector<Effect>, std::vector<Effect>> split;
  for (Effect e : selected) {
    (e == Effect::kCompliance || e == Effect::kJointPosition ? split.first : split.second).push_back(e);
  }
  return split;
}

// Whether the base tilts under the payload's moment (structure_nuisance.h),
// tested two ways. Beside the selected effects: the tilt's terms cut their
// held-out error by min_cv_gain, and run by run; then the selected effects
// that no longer earn their place beside it go to `explained`. In place of
// the effects it resembles (compliance, joint centres), which can take up
// a tilt so far that nothing is left for it beside them: the two are
// non-nested explanations, tied as two effects are (diagnose.cpp's
// Verdicts): the tilt takes up most of their gain, and they do not beat it
// run by run. Then the data does not tell them apart, and they go to
// `explained`.
BaseTiltCheck TestBaseTilt(const Design& d, const Eigen::VectorXd& prior, Evaluator& plain,
                           const std::vector<Effect>& selected, const DiagnoseOptions& o,
                           std::vector<Effect>* explained) {
  BaseTiltCheck c;
  const auto [resembling, rest] = SplitByTiltLikeness(selected);
  if (resembling.empty()) return c;
  c.tested = true;
  WithStructure tilt(d, prior, BaseTiltColumns(d));
  Evaluator eval(tilt.design, tilt.gram, tilt.prior);
  const double before = plain.Cv(selected), after = eval.Cv(selected), in_place = eval.Cv(rest);
  const auto gain = [before](double cv) { return before > 0.0 ? (before - cv) / before : 0.0; };
  c.cv_gain = gain(after);
  c.in_place_cv_gain = gain(in_place);
  c.tilts = c.cv_gain >= o.min_cv_gain &&
            PairedGainIsSignificant(LogGains(eval.FoldSse(selected), plain.FoldSse(selected)), o.significance);
  const double without = plain.Cv(rest);  // neither the tilt nor the effects it resembles
  const double theirs = without > 0.0 ? (without - before) / without : 0.0;
  const double tilts_instead = without > 0.0 ? (without - in_place) / without : 0.0;
  c.in_place_share = theirs > 0.0 ? tilts_instead / theirs : 0.0;
  const auto theirs_over_tilt = [&] { return LogGains(plain.FoldSse(selected), eval.FoldSse(rest)); };
  c.replaces = !c.tilts && Tied(tilts_instead, theirs, theirs_over_tilt, o);
  if (c.tilts) *explained = RedundantBeside(eval, after, selected, o);
  if (c.replaces) *explained = resembling;
  return c;
}

// The drifting clock's columns beside the selected effects, and what its
// drift is scored against. Without encoders the offset is free in both (it
// is a lag equal on every leg, which only the drift parts from a drive's).
// With encoders the offset is theirs, already removed (time_offset.h), and
// must not be freed again: the drift alone, about the offset's own epoch
// (its column less its projection on the offset's), against the design as
// it is. Without encoders the offset alone (`steady`) also tells whether a
// selected servo_lag is no more than the clock's (TestClockOffset).
struct ClockNuisance {
  ClockNuisance(const Design& d, const Eigen::VectorXd& prior) {
    const Eigen::MatrixXd clock = DriftingOffsetColumns(d);
    if (d.has_encoder) {
      const double epoch =
          clock.col(0).squaredNorm() > 0.0 ? clock.col(0).dot(clock.col(1)) / clock.col(0).squaredNorm() : 0.0;
      drifting = std::make_unique<WithStructure>(d, prior, clock.col(1) - epoch * clock.col(0));
      return;
    }
    steady = std::make_unique<WithStructure>(d, prior, clock.leftCols(1));
    drifting = std::make_unique<WithStructure>(d, prior, clock);
    steady_eval = std::make_unique<Evaluator>(steady->design, steady->gram, steady->prior);
  }
  // What the drift is scored against: the offset alone, or `plain` (the
  // design as it is) with encoders.
  Evaluator& Still(Evaluator& plain) { return steady_eval ? *steady_eval : plain; }
  std::unique_ptr<WithStructure> steady, drifting;
  std::unique_ptr<Evaluator> steady_eval;
};

// Whether the tracker's clock drifts from the controller's, beside the
// selected effects (ClockNuisance). The drift ρ must stand out of its own
// uncertainty (|ρ| > kTimeOffsetSignificance·σ, as the offset must) and
// cut the held-out error run by run; then it drifts if the cut is
// min_cv_gain, or if a selected effect no longer earns its place beside
// the drifting clock (without encoders: a servo lag equal on every leg
// that only the clock's mean made; the constant offset beside it takes
// that up too, so this arm rests on ρ's own evidence). Those effects go
// to `explained`.
ClockDriftCheck TestClockDrift(ClockNuisance& clock, Evaluator& plain, const std::vector<Effect>& selected,
                               const DiagnoseOptions& o, std::vector<Effect>* explained) {
  ClockDriftCheck c;
  if (clock.drifting->design.samples() == 0) return c;
  c.tested = true;
  const WithStructure& drifting = *clock.drifting;
  Evaluator& still = clock.Still(plain);
  Evaluator eval(drifting.design, drifting.gram, drifting.prior);
  const double before = still.Cv(selected), after = eval.Cv(selected);
  c.cv_gain = before > 0.0 ? (before - after) / before : 0.0;

  const ColumnRange& n = drifting.design.nuisance;  // ρ is its last column
  const Coefficient rho = FitCoefficient(drifting.design, drifting.gram, ColumnsOf(drifting.design, selected),
                                         n.begin + n.count - 1, drifting.prior);
  c.drift = rho.value;
  c.sigma = rho.sigma;

  c.run_by_run = c.cv_gain > 0.0 && std::abs(c.drift) > kTimeOffsetSignificance * c.sigma &&
                 PairedGainIsSignificant(LogGains(eval.FoldSse(selected), still.FoldSse(selected)), o.significance);
  if (!c.run_by_run) return c;
  *explained = RedundantBeside(eval, after, selected, o);
  c.drifts = c.cv_gain >= o.min_cv_gain || !explained->empty();
  if (!c.drifts) explained->clear();
  return c;
}

// Without encoders, whether the selected servo_lag is the clock's constant
// offset (ClockNuisance's `steady` design): it no longer earns its place
// beside δ. δ is fitted beside the other selected effects, as it would
// stand in for the lag.
ClockOffsetCheck TestClockOffset(ClockNuisance& clock, const std::vector<Effect>& selected, const DiagnoseOptions& o) {
  ClockOffsetCheck c;
  if (clock.steady == nullptr || !Contains(selected, Effect::kServoLag)) return c;
  c.tested = true;
  const WithStructure& steady = *clock.steady;
  const ColumnRange& n = steady.design.nuisance;
  const Coefficient offset =
      FitCoefficient(steady.design, steady.gram, ColumnsOf(steady.design, Without(selected, Effect::kServoLag)),
                     n.begin + n.count - 1, steady.prior);
  c.offset_s = offset.value;
  c.sigma_s = offset.sigma;
  Evaluator& eval = *clock.steady_eval;
  c.replaces_lag = !EarnsItsPlace(eval, eval.Cv(selected), selected, Effect::kServoLag, o);
  return c;
}

// `unknown` when every selected effect could be the unknown's, else the
// effects and the unknown.
void ConcludeWithUnknown(Diagnosis* out) {
  const bool all = std::all_of(out->effects.begin(), out->effects.end(), [&](const EffectResult& r) {
    return !Contains(out->selected, r.effect) || r.ambiguous_with_unknown;
  });
  out->conclusion = all ? Conclusion::kUnknown : Conclusion::kEffectsAndUnknown;
}

// What an unknown is, for what a calibration may do with the effects it
// could explain: the platform's own mechanics (a stand-in moves the
// platform as it would), or anything else (a clock, structure).
enum class UnknownKind { kMechanics, kOther };

// An effect the unknown could explain is not identified (so no calibration
// applies it by default): ambiguous with the unknown, `why` saying what the
// unknown is. It stands in for mechanics only while every unknown it is
// ambiguous with is mechanics.
void MarkExplainedByUnknown(const std::vector<Effect>& explained, const std::string& why, Diagnosis* out,
                            UnknownKind kind = UnknownKind::kOther) {
  if (explained.empty()) return;
  for (EffectResult& r : out->effects) {
    if (!Contains(explained, r.effect)) continue;
    r.verdict = Verdict::kAmbiguous;
    r.stands_in_for_mechanics =
        kind == UnknownKind::kMechanics && (!r.ambiguous_with_unknown || r.stands_in_for_mechanics);
    r.ambiguous_with_unknown = true;
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
  if (residual != std::string::npos)
    note.insert(residual, "; " + what);
  else if (out->structure.structured)
    note += "; " + what;
  else
    note = what + kResidual + note;
}

// Something outside the vocabulary that a check found: said in what is
// left (`what`), each effect it makes redundant ambiguous with it (`what`,
// then `advice`: the measurement that tells them apart), and the
// conclusion naming `unknown`.
void MarkUnknown(const std::string& what, const std::vector<Effect>& explained, const std::string& advice,
                 Diagnosis* out, UnknownKind kind = UnknownKind::kOther) {
  NoteUnknown(what, out);
  MarkExplainedByUnknown(explained, what + advice, out, kind);
  out->conclusion = WithUnknown(out->conclusion);
}

// The effects a base tilt can stand in for, as a note names them.
std::string TiltLikeNames(const std::vector<Effect>& effects) {
  std::string names;
  for (Effect e : effects) {
    names +=
        (names.empty() ? "" : " and ") + std::string(e == Effect::kJointPosition ? "joint centres" : EffectName(e));
  }
  return names;
}

// The base's tilt is outside the vocabulary: said in what is left, and an
// effect it makes redundant, or ties with, is ambiguous with it.
void MarkExplainedByBaseTilt(const std::vector<Effect>& explained, Diagnosis* out) {
  const BaseTiltCheck& c = out->base_tilt;
  if (c.tilts) {
    const std::string what = fmt::format(
        "the base tilts under the payload's moment (a rotational give of the base mount or floor beside the "
        "selected effects predicts the held-out runs {:.0f}% better)",
        100 * c.cv_gain);
    MarkUnknown(what, explained,
                ", and this effect no longer earns its place beside it; an inclinometer on the base tells the tilt "
                "apart",
                out, UnknownKind::kMechanics);
  } else if (c.replaces) {
    const std::string what = fmt::format(
        "the base may tilt under the payload's moment (in place of {}, a rotational give of the base mount or floor "
        "predicts the held-out runs {}: the data does not tell them apart)",
        TiltLikeNames(explained), HeldOutChange(c.in_place_cv_gain));
    MarkUnknown(what, explained, "; an inclinometer on the base tells them apart", out, UnknownKind::kMechanics);
  }
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
  MarkUnknown(what, explained,
              ", and this effect no longer earns its place beside it; trigger the tracker from the controller's clock "
              "(or PTP) and measure again",
              out);
}

// A lag only a clock offset could also be, from the tracker alone: said in
// what is left, and servo_lag ambiguous with it.
void MarkLagThatMayBeTheClocks(Diagnosis* out) {
  const ClockOffsetCheck& c = out->clock_offset;
  if (!c.replaces_lag) return;
  const std::string what = fmt::format(
      "the lag may be the tracker's clock running {}: it predicts the held-out runs as well, and without encoder "
      "columns a lag equal on every leg and a pure delay is one with it",
      ClockAhead(c.offset_s, c.sigma_s));
  MarkUnknown(what, {Effect::kServoLag},
              "; record the encoders (leg_enc_*) or trigger the tracker from the controller's clock and measure again",
              out);
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

}  // namespace

void CheckBeyondTheVocabulary(const Design& d, const Eigen::VectorXd& prior, Evaluator& plain, const DiagnoseOptions& o,
                              Diagnosis* out) {
  MarkExplainedByStructure(ExplainedByStructure(d, prior, plain, out->selected, out->structure, o), out);
  std::vector<Effect> tilt_explained;
  out->base_tilt = TestBaseTilt(d, prior, plain, out->selected, o, &tilt_explained);
  MarkExplainedByBaseTilt(tilt_explained, out);
  std::vector<Effect> clock_explained;
  ClockNuisance clock(d, prior);
  out->clock_drift = TestClockDrift(clock, plain, out->selected, o, &clock_explained);
  MarkExplainedByClockDrift(clock_explained, out);
  if (!out->clock_drift.drifts) {  // a drifting clock has freed the offset already
    out->clock_offset = TestClockOffset(clock, out->selected, o);
    MarkLagThatMayBeTheClocks(out);
  }
  MarkLagNotInTheDrives(d, out);
}

}  // namespace edsp::gap
