#include "edsp/gap/benchmark.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/gap/closed_loop.h"
#include "edsp/diagnosis/heldout_score.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "draws.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {

namespace {

void Progress(const BenchmarkOptions& o, int done, int total, const std::string& what) {
  if (!o.progress) return;
  constexpr int kWidth = 30;
  const int filled = total ? kWidth * done / total : kWidth;
  std::fprintf(stderr, "\r[%s%s] %d/%d %-40.40s", std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(), done, total, what.c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

// What a generator hands the scorer: the truth, kept from the diagnosis,
// and the measurement CSV the diagnosis sees.
struct Drawn {
  ScenarioKind kind = ScenarioKind::kNone;
  std::vector<std::string> truth;
  std::string description;
  std::string csv_path;
  double noise_sigma_m = 0.0;  // the tracker noise added, 1-σ per axis
  double simulate_s = 0.0;
  // On edsp's rig: how it ran, for the closed loop.
  std::optional<OfflineRunOptions> run;
  RigEffects effects;
};

// A scenario of the vocabulary (or effect-free) scored short of its truth:
// a false effect identified, a single effect not identified first, a pair
// not both identified. Out of vocabulary there is no truth to compare with.
bool IsMiss(const ScenarioScore& s) {
  switch (s.kind) {
    case ScenarioKind::kNone: return s.false_identified;
    case ScenarioKind::kSingle: return s.false_identified || !s.top_identified_true;
    case ScenarioKind::kPair:
    case ScenarioKind::kWholeRig: return s.false_identified || !s.all_identified;
    case ScenarioKind::kOutOfVocabulary: return false;
  }
  return false;
}

ScenarioScore Score(const Drawn& s, const Diagnosis& d) {
  ScenarioScore score;
  score.kind = s.kind;
  score.truth = s.truth;
  score.description = s.description;
  score.conclusion = d.conclusion;
  auto truth_has = [&](const std::string& name) {
    return std::find(s.truth.begin(), s.truth.end(), name) != s.truth.end();
  };
  // The report's ranking, pseudo-effects included (`none` or `unknown` may
  // be the top); only an effect of the vocabulary counts as identified.
  std::vector<std::string>& identified = score.identified;
  for (const RankedEntry& e : Ranking(d)) {
    const std::string name = RankedName(e);
    const Verdict verdict = RankedVerdict(e);
    if (score.top.empty()) score.top = name;
    if (verdict == Verdict::kIdentified || verdict == Verdict::kAmbiguous) score.found.push_back(name);
    if (verdict != Verdict::kIdentified || e.kind != RankedEntry::Kind::kEffect) continue;
    identified.push_back(name);
    score.false_identified = score.false_identified || !truth_has(name);
  }
  score.top_true = truth_has(score.top);
  score.top_identified_true = !identified.empty() && truth_has(identified.front());
  auto all_in = [&](const std::vector<std::string>& names) {
    return std::all_of(s.truth.begin(), s.truth.end(),
                       [&](const std::string& t) { return std::find(names.begin(), names.end(), t) != names.end(); });
  };
  // On a whole rig, joint centres fitted move each leg's length as well: a
  // leg offset is then not a separate effect to name.
  const auto covers_leg_offsets = [&](std::vector<std::string>* names) {
    const auto has = [&](const char* n) { return std::find(names->begin(), names->end(), n) != names->end(); };
    if (s.kind == ScenarioKind::kWholeRig && has("joint_position") && !has("leg_offset"))
      names->push_back("leg_offset");
  };
  covers_leg_offsets(&score.found);
  covers_leg_offsets(&identified);
  score.all_found = all_in(score.found);
  score.all_identified = all_in(identified);
  score.before_rms_m = d.holdout_before.rms_m;
  score.after_rms_m = d.holdout_after.rms_m;
  score.shrink = d.shrink;
  score.noise_floor_m = d.noise_floor_rms_m;
  score.noise_sigma_m = s.noise_sigma_m;
  score.gap_shrink = GapShrink(score.before_rms_m, score.after_rms_m, std::sqrt(3.0) * s.noise_sigma_m);
  score.diagnose_s = d.seconds;
  score.miss = IsMiss(score);
  return score;
}

// Would the true effects have predicted the held-out runs better than the
// selected ones? Both fitted the same way on the same data.
void CompareWithTheTruth(const PlatformModel& model, const MeasurementData& data, const Diagnosis& d,
                         ScenarioScore* score) {
  std::vector<Effect> truth;
  for (const std::string& name : score->truth) {
    Effect e;
    if (ParseEffect(name, &e)) truth.push_back(e);
  }
  const DiagnoseOptions options;
  score->truth_heldout_rms_m = HeldOutRmsOf(model, data, options, d, truth);
  score->found_heldout_rms_m = HeldOutRmsOf(model, data, options, d, d.selected);
  const double truth2 = score->truth_heldout_rms_m * score->truth_heldout_rms_m;
  const double found2 = score->found_heldout_rms_m * score->found_heldout_rms_m;
  score->data_tell_apart = truth2 < (1.0 - options.min_cv_gain) * found2;
}

// A whole rig's true effects that were not identified: can these runs show
// each one at all? The true effects fitted without it, against all of them.
void SplitMissedByWhatTheRunsShow(const PlatformModel& model, const MeasurementData& data, const Diagnosis& d,
                                  const std::vector<std::string>& identified, ScenarioScore* score) {
  std::vector<Effect> truth;
  for (const std::string& name : score->truth) {
    Effect e;
    if (ParseEffect(name, &e)) truth.push_back(e);
  }
  const DiagnoseOptions options;
  double all2 = -1.0;
  for (const Effect e : truth) {
    const std::string name = EffectName(e);
    if (std::find(identified.begin(), identified.end(), name) != identified.end()) continue;
    if (all2 < 0.0) all2 = std::pow(HeldOutRmsOf(model, data, options, d, truth), 2);
    std::vector<Effect> without = truth;
    without.erase(std::remove(without.begin(), without.end(), e), without.end());
    const double without2 = std::pow(HeldOutRmsOf(model, data, options, d, without), 2);
    (all2 < (1.0 - options.min_cv_gain) * without2 ? score->missed_shown : score->missed_unshown).push_back(name);
  }
  score->all_shown_identified = score->missed_shown.empty();
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Scenario k on edsp's own rig (edsp-sim rig's offline run).
Drawn DrawOnRig(const BenchmarkOptions& options, const std::string& config, Rng& frames, int k, double rated_payload_kg,
                const std::string& dir) {
  const Scenario s =
      options.whole_rigs ? DrawEveryClassRig(options.seed, k, rated_payload_kg) : DrawScenario(options.seed, k);
  OfflineRunOptions run;
  run.motions = options.motions;
  run.paper.stops = 5;
  run.paper.dwell_s = 0.5;
  run.paper.max_speed_m_s = 0.25;
  run.paper.max_speed_rad_s = 0.5;  // mixed motions: half of each
  run.pr_mode = s.compensation;
  run.tracker.noise_sigma_m = options.tracker_noise_m;
  run.tracker.rate_hz = options.tracker_rate_hz;
  run.tracker.seed = options.seed * 7919 + static_cast<std::uint64_t>(k);
  run.tracker.X_TB = DrawTrackerStand(frames);
  run.out_dir = dir;
  Drawn drawn;
  drawn.kind = options.whole_rigs ? ScenarioKind::kWholeRig : KindOfEffects(s.truth.size());
  for (Effect e : s.truth) drawn.truth.push_back(EffectName(e));
  drawn.description = s.description;
  drawn.noise_sigma_m = run.tracker.noise_sigma_m;
  drawn.run = run;
  drawn.effects = s.effects;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    drawn.csv_path = RunOffline(config, s.effects, run).csv_path;
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("scenario {} ({}): {}", k, s.description, e.what()));
  }
  drawn.simulate_s = SecondsSince(t0);
  return drawn;
}

// Scenario k on the blind rig (blindrig/): its own kinematics, effects,
// motions and tracker draw; only the config's numbers are shared.
Drawn DrawOnBlindRig(const BenchmarkOptions& options, const PlatformConfig& config, int k, double rated_payload_kg,
                     const std::string& dir) {
  const std::optional<bool> encoders = options.encoders == EncoderColumns::kDrawn
                                           ? std::nullopt
                                           : std::optional<bool>(options.encoders == EncoderColumns::kWith);
  const blind::BlindScenario s = options.whole_rigs ? blind::DrawBlindEveryClassRig(options.seed, k, rated_payload_kg)
                                                    : blind::DrawBlindScenario(options.seed, k, encoders);
  blind::BlindRigSetup setup = blind::SetupFromConfig(config);
  setup.motions = options.motions;
  Drawn drawn;
  const std::optional<ScenarioKind> kind = ParseScenarioKind(s.kind);
  if (!kind)
    throw std::runtime_error(fmt::format("blind scenario {}: a kind the benchmark cannot score: {}", k, s.kind));
  drawn.kind = *kind;
  drawn.truth = s.truth;
  drawn.description = s.description;
  drawn.noise_sigma_m = s.tracker.noise_m;
  drawn.csv_path = dir + "/measurement.csv";
  const auto t0 = std::chrono::steady_clock::now();
  std::string csv;
  try {
    csv = blind::GenerateMeasurementCsv(setup, s.effects, s.tracker);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("blind scenario {} ({}): {}", k, s.description, e.what()));
  }
  std::ofstream out(drawn.csv_path);
  out << csv;
  if (!out) throw std::runtime_error(drawn.csv_path + ": cannot write");
  drawn.simulate_s = SecondsSince(t0);
  return drawn;
}

// A perfect model leaves the tracker's noise: 1 − floor/before.
double AttainableShrink(const ScenarioScore& s) { return std::max(0.0, Shrink(s.before_rms_m, s.noise_floor_m)); }

void Tally(BenchmarkResult* r) {
  std::vector<double> shrinks, attainable, gap_shrinks, ratios, seconds, whole_ratios;
  for (const ScenarioScore& s : r->scores) {
    seconds.push_back(s.diagnose_s);
    r->misses += s.miss;
    r->misses_told_apart += s.miss && s.data_tell_apart;
    r->any_false_identified += s.false_identified;
    if (s.kind == ScenarioKind::kNone) {
      ++r->clean;
      r->clean_nothing_identified += !s.false_identified;
      r->clean_none += s.conclusion == Conclusion::kNone;
      continue;
    }
    if (s.kind == ScenarioKind::kOutOfVocabulary) {
      ++r->out_of_vocabulary;
      r->out_of_vocabulary_unknown += s.conclusion == Conclusion::kUnknown && !s.false_identified;
      continue;
    }
    r->extra_identified += s.false_identified;
    if (s.kind == ScenarioKind::kWholeRig) {
      const double floor = std::sqrt(3.0) * s.noise_sigma_m;
      ++r->whole;
      r->whole_all_named += s.all_shown_identified;
      r->whole_all_identified += s.all_identified;
      r->whole_unshown += static_cast<int>(s.missed_unshown.size());
      r->whole_closed += s.after_rms_m <= kWholeRigClosedFloorRatio * floor;
      r->whole_wrong += s.false_identified;
      whole_ratios.push_back(floor > 0 ? s.after_rms_m / floor : 0.0);
    } else if (s.kind == ScenarioKind::kSingle) {
      ++r->single;
      r->single_top_true += s.top_true;
      r->single_identified_top_true += s.top_identified_true;
    } else {
      ++r->pairs;
      r->pairs_both += s.all_found;
      r->pairs_both_identified += s.all_identified;
    }
    shrinks.push_back(s.shrink);
    attainable.push_back(AttainableShrink(s));
    gap_shrinks.push_back(s.gap_shrink);
    ratios.push_back(s.noise_floor_m > 0 ? s.after_rms_m / s.noise_floor_m : 0.0);
  }
  r->median_shrink = Median(shrinks);
  r->median_attainable_shrink = Median(attainable);
  r->median_gap_shrink = Median(gap_shrinks);
  r->median_after_over_noise = Median(ratios);
  r->median_diagnose_s = Median(seconds);
  r->median_whole_after_over_floor = Median(whole_ratios);
  std::vector<double> measured, predicted, measured_gap, predicted_gap;
  for (const ScenarioScore& s : r->scores) {
    if (!s.closed_loop || s.kind == ScenarioKind::kNone || s.kind == ScenarioKind::kOutOfVocabulary) continue;
    ++r->closed_loop;
    measured.push_back(s.closed_shrink);
    predicted.push_back(s.closed_predicted_shrink);
    measured_gap.push_back(s.closed_gap_shrink);
    predicted_gap.push_back(s.closed_predicted_gap_shrink);
    if (std::abs(s.closed_shrink - s.closed_predicted_shrink) >= 0.10) r->closed_disagree.push_back(s.index);
    if (std::abs(s.closed_gap_shrink - s.closed_predicted_gap_shrink) >= 0.10)
      r->closed_gap_disagree.push_back(s.index);
  }
  r->median_closed_shrink = Median(measured);
  r->median_closed_predicted_shrink = Median(predicted);
  r->median_closed_gap_shrink = Median(measured_gap);
  r->median_closed_predicted_gap_shrink = Median(predicted_gap);
}

double Rate(int a, int b) { return b ? static_cast<double>(a) / b : 0.0; }

// The issue's targets (docs/diagnosis.md): score, measured rate, target, met.
struct Target {
  const char* name;
  double rate;
  double target;
  bool at_most;  // the rate must not exceed the target
  int scenarios;
};

std::vector<Target> Targets(const BenchmarkResult& r) {
  return {{"single_top_identified_true", Rate(r.single_identified_top_true, r.single), 0.95, false, r.single},
          {"pairs_both_identified", Rate(r.pairs_both_identified, r.pairs), 0.85, false, r.pairs},
          {"effect_free_none", Rate(r.clean_none, r.clean), 1.0, false, r.clean},
          {"out_of_vocabulary_unknown", Rate(r.out_of_vocabulary_unknown, r.out_of_vocabulary), 0.90, false,
           r.out_of_vocabulary},
          {"any_false_identified", Rate(r.any_false_identified, static_cast<int>(r.scores.size())), 0.05, true,
           static_cast<int>(r.scores.size())},
          {"median_shrink", r.median_shrink, 0.85, false, r.single + r.pairs},
          {"median_gap_shrink", r.median_gap_shrink, 0.85, false, r.single + r.pairs},
          {"whole_rig_all_shown_named", Rate(r.whole_all_named, r.whole), 0.90, false, r.whole},
          {"whole_rig_closed", Rate(r.whole_closed, r.whole), 0.90, false, r.whole},
          {"whole_rig_wrong_named", Rate(r.whole_wrong, r.whole), 0.05, true, r.whole}};
}

bool Met(const Target& t) { return t.scenarios == 0 || (t.at_most ? t.rate <= t.target : t.rate >= t.target); }

}  // namespace

BenchmarkResult RunBenchmark(const BenchmarkOptions& options) {
  if (options.encoders != EncoderColumns::kDrawn && options.generator != Generator::kBlind) {
    throw std::invalid_argument(std::string("benchmark encoders '") + EncoderColumnsName(options.encoders) +
                                "': only the blind generator draws them (the rig's tracker always has encoders)");
  }
  BenchmarkResult result;
  result.options = options;
  const std::string config = options.config_path.empty() ? SourcePath("config/huang2021.toml") : options.config_path;
  const PlatformConfig platform = LoadConfigFile(config);
  const PlatformModel model(platform);
  const std::string root =
      options.keep_dir.empty()
          ? (std::filesystem::temp_directory_path() / fmt::format("edsp-gap-bench-{}", ::getpid())).string()
          : options.keep_dir;
  const double rated_payload_kg = options.whole_rigs ? WholeRigRatedPayload(model) : 0.0;
  Rng frames(options.seed);
  for (int k = 0; k < options.scenarios; ++k) {
    Progress(options, k, options.scenarios, fmt::format("scenario {}: simulating", k));
    const std::string dir = fmt::format("{}/scenario-{:03d}", root, k);
    std::filesystem::create_directories(dir);
    const Drawn drawn = options.generator == Generator::kBlind
                            ? DrawOnBlindRig(options, platform, k, rated_payload_kg, dir)
                            : DrawOnRig(options, config, frames, k, rated_payload_kg, dir);
    Progress(options, k, options.scenarios, fmt::format("scenario {}: diagnosing", k));
    // Blind: the diagnosis sees the measurement CSV and the nominal model only.
    const MeasurementData data = LoadMeasurement(drawn.csv_path);
    const Diagnosis d = Diagnose(model, data);
    ScenarioScore score = Score(drawn, d);
    if (score.miss) CompareWithTheTruth(model, data, d, &score);
    if (score.kind == ScenarioKind::kWholeRig) SplitMissedByWhatTheRunsShow(model, data, d, score.identified, &score);
    score.index = k;
    score.simulate_s = drawn.simulate_s;
    if (drawn.run && !options.closed_loop_motions.empty()) {
      Progress(options, k, options.scenarios, fmt::format("scenario {}: closed loop", k));
      const auto t0 = std::chrono::steady_clock::now();
      try {
        const MotionCheck loop =
            MeasureClosedLoop(model, config, drawn.effects, *drawn.run, ModelJson(d), options.closed_loop_motions, dir);
        score.closed_loop = true;
        score.closed_before_rms_m = loop.before.rms_m;
        score.closed_after_rms_m = loop.after.rms_m;
        score.closed_predicted_rms_m = loop.predicted ? loop.predicted->rms_m : 0.0;
        score.closed_shrink = loop.shrink;
        score.closed_predicted_shrink = Shrink(loop.before.rms_m, score.closed_predicted_rms_m);
        const double floor = std::sqrt(3.0) * drawn.noise_sigma_m;
        score.closed_gap_shrink = GapShrink(loop.before.rms_m, loop.after.rms_m, floor);
        score.closed_predicted_gap_shrink = GapShrink(loop.before.rms_m, score.closed_predicted_rms_m, floor);
      } catch (const std::exception& e) {
        // One scenario's model the kinematics refuses (or a run that fails)
        // is that scenario's result, not the benchmark's end.
        std::fprintf(stderr, "edsp-gap benchmark: scenario %d (%s), closed loop not run: %s\n", k,
                     drawn.description.c_str(), e.what());
      }
      score.closed_loop_s = SecondsSince(t0);
    }
    if (!options.keep_dir.empty()) {
      std::ofstream(dir + "/diagnosis.json") << ToJson(d).dump(2) << "\n";
      std::ofstream(dir + "/truth.txt") << ScenarioKindName(drawn.kind) << ": " << drawn.description << "\n";
    } else {
      std::filesystem::remove_all(dir);
    }
    result.scores.push_back(score);
  }
  Progress(options, options.scenarios, options.scenarios, "done");
  if (options.keep_dir.empty()) std::filesystem::remove_all(root);
  Tally(&result);
  return result;
}

nlohmann::json ToJson(const BenchmarkResult& r) {
  nlohmann::json j;
  j["mode"] = r.options.whole_rigs ? "whole" : "effects";
  j["generator"] = GeneratorName(r.options.generator);
  j["encoders"] = EncoderColumnsName(r.options.encoders);
  j["seed"] = r.options.seed;
  j["scenarios"] = r.scores.size();
  j["tracker_noise_m"] = r.options.tracker_noise_m;
  j["single_effect"] = {{"scenarios", r.single},
                        {"top_ranked_true", r.single_top_true},
                        {"rate", Rate(r.single_top_true, r.single)},
                        {"top_identified_true", r.single_identified_top_true},
                        {"identified_rate", Rate(r.single_identified_top_true, r.single)}};
  j["two_effects"] = {{"scenarios", r.pairs},
                      {"both_found", r.pairs_both},
                      {"rate", Rate(r.pairs_both, r.pairs)},
                      {"both_identified", r.pairs_both_identified},
                      {"identified_rate", Rate(r.pairs_both_identified, r.pairs)}};
  j["effect_free"] = {{"scenarios", r.clean},
                      {"nothing_identified", r.clean_nothing_identified},
                      {"rate", Rate(r.clean_nothing_identified, r.clean)},
                      {"conclusion_none", r.clean_none},
                      {"none_rate", Rate(r.clean_none, r.clean)}};
  j["out_of_vocabulary"] = {{"scenarios", r.out_of_vocabulary},
                            {"unknown", r.out_of_vocabulary_unknown},
                            {"rate", Rate(r.out_of_vocabulary_unknown, r.out_of_vocabulary)}};
  j["whole_rig"] = {{"scenarios", r.whole},
                    {"all_shown_named", r.whole_all_named},
                    {"all_named", r.whole_all_identified},
                    {"effects_below_what_the_runs_show", r.whole_unshown},
                    {"closed", r.whole_closed},
                    {"closed_within_floor_times", kWholeRigClosedFloorRatio},
                    {"wrong_named", r.whole_wrong},
                    {"median_after_over_floor", r.median_whole_after_over_floor}};
  j["any_false_identified"] = {{"scenarios", r.any_false_identified},
                               {"rate", Rate(r.any_false_identified, static_cast<int>(r.scores.size()))}};
  j["with_effects_extra_identified"] = r.extra_identified;  // a false effect identified beside the true ones
  j["median_shrink"] = r.median_shrink;
  j["median_attainable_shrink"] = r.median_attainable_shrink;
  j["median_gap_shrink"] = r.median_gap_shrink;
  j["misses"] = {{"scenarios", r.misses}, {"truth_predicts_better", r.misses_told_apart}};
  j["median_after_over_noise_floor"] = r.median_after_over_noise;
  j["median_diagnose_s"] = r.median_diagnose_s;
  j["closed_loop"] = {
      {"motions", r.options.generator == Generator::kRig ? r.options.closed_loop_motions : std::vector<std::string>{}},
      {"scenarios", r.closed_loop},
      {"median_measured_shrink", r.median_closed_shrink},
      {"median_predicted_shrink", r.median_closed_predicted_shrink},
      {"median_measured_gap_shrink", r.median_closed_gap_shrink},
      {"median_predicted_gap_shrink", r.median_closed_predicted_gap_shrink},
      {"disagree_by_10_points", r.closed_disagree},
      {"disagree_by_10_gap_points", r.closed_gap_disagree}};
  j["targets"] = nlohmann::json::array();
  for (const Target& t : Targets(r)) {
    j["targets"].push_back({{"score", t.name},
                            {"measured", t.rate},
                            {"target", t.target},
                            {"at_most", t.at_most},
                            {"scenarios", t.scenarios},
                            {"met", Met(t)}});
  }
  j["results"] = nlohmann::json::array();
  for (const ScenarioScore& s : r.scores) {
    j["results"].push_back({{"index", s.index},
                            {"kind", ScenarioKindName(s.kind)},
                            {"truth", s.truth},
                            {"description", s.description},
                            {"found", s.found},
                            {"identified", s.identified},
                            {"top", s.top},
                            {"conclusion", ConclusionName(s.conclusion)},
                            {"top_true", s.top_true},
                            {"all_found", s.all_found},
                            {"top_identified_true", s.top_identified_true},
                            {"all_identified", s.all_identified},
                            {"false_identified", s.false_identified},
                            {"holdout_before_rms_m", s.before_rms_m},
                            {"holdout_after_rms_m", s.after_rms_m},
                            {"shrink", s.shrink},
                            {"attainable_shrink", AttainableShrink(s)},
                            {"noise_floor_rms_m", s.noise_floor_m},
                            {"noise_sigma_m", s.noise_sigma_m},
                            {"gap_shrink", s.gap_shrink},
                            {"simulate_s", s.simulate_s},
                            {"diagnose_s", s.diagnose_s}});
    if (s.miss) {
      j["results"].back()["miss"] = {{"truth_heldout_rms_m", s.truth_heldout_rms_m},
                                     {"found_heldout_rms_m", s.found_heldout_rms_m},
                                     {"truth_predicts_better", s.data_tell_apart}};
    }
    if (s.kind == ScenarioKind::kWholeRig) {
      j["results"].back()["missed"] = {{"shown", s.missed_shown}, {"below_what_the_runs_show", s.missed_unshown}};
    }
    if (s.closed_loop) {
      j["results"].back()["closed_loop"] = {{"before_rms_m", s.closed_before_rms_m},
                                            {"after_rms_m", s.closed_after_rms_m},
                                            {"predicted_after_rms_m", s.closed_predicted_rms_m},
                                            {"shrink", s.closed_shrink},
                                            {"predicted_shrink", s.closed_predicted_shrink},
                                            {"gap_shrink", s.closed_gap_shrink},
                                            {"predicted_gap_shrink", s.closed_predicted_gap_shrink},
                                            {"seconds", s.closed_loop_s}};
    }
  }
  return j;
}

void PrintBenchmark(const BenchmarkResult& r) {
  std::printf("generator %s, seed %llu\n%-3s %-18s %-40s %-40s %-16s %8s %8s %7s %7s\n",
              GeneratorName(r.options.generator), static_cast<unsigned long long>(r.options.seed), "#", "kind", "truth",
              "found (ranked)", "conclusion", "before", "after", "shrink", "gap");
  for (const ScenarioScore& s : r.scores) {
    std::printf("%-3d %-18s %-40s %-40s %-16s %6.1fµm %6.1fµm %6.0f%% %6.0f%%\n", s.index, ScenarioKindName(s.kind),
                (s.truth.empty() ? std::string("-") : fmt::format("{}", fmt::join(s.truth, ","))).c_str(),
                (s.found.empty() ? s.top : fmt::format("{}", fmt::join(s.found, ","))).c_str(),
                ConclusionName(s.conclusion), s.before_rms_m * 1e6, s.after_rms_m * 1e6, 100 * s.shrink,
                100 * s.gap_shrink);
  }
  std::printf("\n%-28s %9s %8s %10s %s\n", "score", "measured", "target", "scenarios", "met");
  for (const Target& t : Targets(r)) {
    std::printf("%-28s %8.0f%% %s%5.0f%% %10d %s\n", t.name, 100 * t.rate, t.at_most ? "≤" : "≥", 100 * t.target,
                t.scenarios,
                t.scenarios == 0 ? "-"
                : Met(t)         ? "yes"
                                 : "NO");
  }
  std::printf(
      "\nsingle effect: top-ranked true %d/%d; two effects: both found %d/%d; effect-free: nothing "
      "identified %d/%d; a false effect identified beside true ones in %d\nmedian shrink %.0f%% (a perfect model "
      "%.0f%%: the gap down to the noise floor); of the gap above the tracker's noise %.0f%%; median "
      "after/noise floor %.2f, median diagnosis %.2f s\n",
      r.single_top_true, r.single, r.pairs_both, r.pairs, r.clean_nothing_identified, r.clean, r.extra_identified,
      100 * r.median_shrink, 100 * r.median_attainable_shrink, 100 * r.median_gap_shrink, r.median_after_over_noise,
      r.median_diagnose_s);
  if (r.whole > 0) {
    std::printf(
        "whole rigs: every effect the runs show identified (leg offsets by joint centres) %d/%d (every true "
        "effect %d/%d; %d effects below what the runs show); held out within %.1f× the noise floor %d/%d "
        "(median %.2f×); a false effect identified %d/%d\n",
        r.whole_all_named, r.whole, r.whole_all_identified, r.whole, r.whole_unshown, kWholeRigClosedFloorRatio,
        r.whole_closed, r.whole, r.median_whole_after_over_floor, r.whole_wrong, r.whole);
  }
  std::printf(
      "misses (a true effect not identified, a false one identified): %d, of which the true effects "
      "predict the held-out runs better in %d (the others the data cannot tell apart)\n",
      r.misses, r.misses_told_apart);
  if (r.closed_loop > 0) {
    std::printf(
        "\nclosed loop on %s (the model applied by the kinematics, rig with its effects), %d scenarios with "
        "effects:\n%-3s %-40s %8s %8s %8s %8s %10s\n",
        fmt::format("{}", fmt::join(r.options.closed_loop_motions, ",")).c_str(), r.closed_loop, "#", "truth", "before",
        "after", "shrink", "predicted", "pred.shrink");
    for (const ScenarioScore& s : r.scores) {
      if (!s.closed_loop || s.kind == ScenarioKind::kNone) continue;
      std::printf("%-3d %-40s %6.1fµm %6.1fµm %7.0f%% %6.1fµm %9.0f%%\n", s.index,
                  fmt::format("{}", fmt::join(s.truth, ",")).c_str(), s.closed_before_rms_m * 1e6,
                  s.closed_after_rms_m * 1e6, 100 * s.closed_shrink, s.closed_predicted_rms_m * 1e6,
                  100 * s.closed_predicted_shrink);
    }
    std::printf(
        "median shrink measured %.0f%%, predicted %.0f%%, 10 points or more apart in %zu: %s\n"
        "of the gap above the tracker's noise measured %.0f%%, predicted %.0f%%, 10 points or more apart "
        "in %zu: %s\n",
        100 * r.median_closed_shrink, 100 * r.median_closed_predicted_shrink, r.closed_disagree.size(),
        fmt::format("{}", fmt::join(r.closed_disagree, ", ")).c_str(), 100 * r.median_closed_gap_shrink,
        100 * r.median_closed_predicted_gap_shrink, r.closed_gap_disagree.size(),
        fmt::format("{}", fmt::join(r.closed_gap_disagree, ", ")).c_str());
  }
}

}  // namespace edsp::gap
