#include "edsp/diagnosis/benchmark.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"

namespace edsp::gap {

namespace {

using Rng = std::mt19937_64;

double Uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
double Signed(Rng& rng, double lo, double hi) { return Uniform(rng, lo, hi) * (Uniform(rng, 0, 1) < 0.5 ? -1 : 1); }

// Realistic magnitudes for a platform of the paper's size (docs/rig.md).
void Enable(Effect e, Rng& rng, Scenario* s) {
  RigEffects& fx = s->effects;
  switch (e) {
    case Effect::kPassiveRotation: {
      const int variant = static_cast<int>(Uniform(rng, 0, 4));
      if (variant == 0) {
        s->compensation = PrMode::kUnsigned;  // the paper's Eq. (9)
        s->description += "PR compensated unsigned; ";
      } else if (variant == 1) {
        s->compensation = PrMode::kNone;
        s->description += "PR not compensated; ";
      } else if (variant == 2) {
        fx.passive_rotation.enabled = true;
        fx.passive_rotation.pr_sign = -1;     // the other thread hand
        s->description += "screws of the other hand (PR sign −1); ";
      } else {
        fx.passive_rotation.enabled = true;
        const double scale = Uniform(rng, 0, 1) < 0.5 ? Uniform(rng, 0.6, 0.85) : Uniform(rng, 1.15, 1.4);
        fx.passive_rotation.pr_lead_m = 0.010 * scale;
        s->description += fmt::format("PR through a {:.2f}× lead; ", scale);
      }
      break;
    }
    case Effect::kLegOffset:
      fx.leg_offset.enabled = true;
      for (double& v : fx.leg_offset.offset_m) v = Signed(rng, 30e-6, 150e-6);
      s->description += "leg offsets 30–150 µm; ";
      break;
    case Effect::kJointPosition: {
      fx.joint_position.enabled = true;
      std::normal_distribution<double> n(0.0, 100e-6);
      for (int i = 0; i < 6; ++i) {
        for (int a = 0; a < 3; ++a) {
          fx.joint_position.base_m(a, i) = n(rng);
          fx.joint_position.platform_m(a, i) = n(rng);
        }
      }
      s->description += "joint centres σ 100 µm; ";
      break;
    }
    case Effect::kLeadError:
      fx.lead_error.enabled = true;
      for (double& v : fx.lead_error.epsilon) v = Signed(rng, 80e-6, 300e-6);
      s->description += "lead errors 80–300 ppm; ";
      break;
    case Effect::kPeriodicLeadError:
      fx.periodic_lead_error.enabled = true;
      for (int i = 0; i < 6; ++i) {
        fx.periodic_lead_error.amplitude_m[static_cast<std::size_t>(i)] = Uniform(rng, 5e-6, 12e-6);
        fx.periodic_lead_error.phase_rad[static_cast<std::size_t>(i)] = Uniform(rng, 0, 6.283185307179586);
      }
      s->description += "periodic lead error 5–12 µm; ";
      break;
    case Effect::kBacklash:
      fx.backlash.enabled = true;
      for (double& v : fx.backlash.backlash_m) v = Uniform(rng, 15e-6, 60e-6);
      s->description += "backlash 15–60 µm; ";
      break;
    case Effect::kServoLag:
      fx.servo_lag.bandwidth_hz = Uniform(rng, 8.0, 20.0);  // a soft loop without integral action
      fx.servo_lag.integral_time_s = 0.0;
      s->description += fmt::format("servo loop {:.1f} Hz; ", fx.servo_lag.bandwidth_hz);
      break;
    case Effect::kCompliance:
      fx.compliance.enabled = true;
      {
        const double k0 = Uniform(rng, 1e7, 3e7);  // legs of one design, ±15% from assembly
        for (double& v : fx.compliance.stiffness_N_m) v = k0 * Uniform(rng, 0.85, 1.15);
      }
      fx.compliance.mass_kg = Uniform(rng, 400, 1200);
      fx.compliance.com_m = Vector3(0, 0, Uniform(rng, 0.0, 0.3));
      s->description += fmt::format("compliance, {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/µm legs ±15%; ",
                                    fx.compliance.mass_kg, fx.compliance.com_m.z(), fx.compliance.stiffness_N_m[0] * 1e-6);
      break;
    case Effect::kThermalDrift:
      fx.thermal_drift.enabled = true;
      fx.thermal_drift.heating_K_per_m = Uniform(rng, 3.0, 8.0);
      fx.thermal_drift.time_constant_s = Uniform(rng, 600, 1800);
      s->description += fmt::format("thermal drift {:.1f} K/m; ", fx.thermal_drift.heating_K_per_m);
      break;
  }
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void Progress(const BenchmarkOptions& o, int done, int total, const std::string& what) {
  if (!o.progress) return;
  constexpr int kWidth = 30;
  const int filled = total ? kWidth * done / total : kWidth;
  std::fprintf(stderr, "\r[%s%s] %d/%d %-40.40s", std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(), done, total, what.c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

ScenarioScore Score(const Scenario& s, const Diagnosis& d) {
  ScenarioScore score;
  score.scenario = s;
  score.conclusion = d.conclusion;
  const nlohmann::json j = ToJson(d);
  for (const auto& e : j["effects"]) {
    const std::string verdict = e.value("verdict", "");
    if (score.top.empty()) score.top = e.value("name", "");
    if (verdict == "identified" || verdict == "ambiguous") score.found.push_back(e.value("name", ""));
  }
  auto truth_has = [&](const std::string& name) {
    return std::any_of(s.truth.begin(), s.truth.end(), [&](Effect e) { return name == EffectName(e); });
  };
  score.top_true = truth_has(score.top);
  score.all_found = std::all_of(s.truth.begin(), s.truth.end(), [&](Effect e) {
    return std::find(score.found.begin(), score.found.end(), EffectName(e)) != score.found.end();
  });
  for (const auto& e : j["effects"]) {
    Effect parsed;
    if (e.value("verdict", "") == "identified" && ParseEffect(e.value("name", ""), &parsed) && !truth_has(e.value("name", ""))) {
      score.false_identified = true;
    }
  }
  score.before_rms_m = d.holdout_before.rms_m;
  score.after_rms_m = d.holdout_after.rms_m;
  score.shrink = d.shrink;
  score.noise_floor_m = d.noise_floor_rms_m;
  score.diagnose_s = d.seconds;
  return score;
}

}  // namespace

Scenario DrawScenario(std::uint64_t seed, int index) {
  Rng rng(seed * 1000003ull + static_cast<std::uint64_t>(index));
  Scenario s;
  // Every rig has a drive loop; a well-tuned one (integral action) leaves
  // no lag worth the name: the effect-free baseline.
  s.effects.servo_lag.integral_time_s = 0.05;
  s.effects.servo_lag.torque_limit_N_m = 15.0;  // motors sized for the heaviest payload drawn
  const int kind = index % 5;
  const int count = kind == 0 ? 0 : (kind <= 2 ? 1 : 2);
  std::vector<Effect> pool = AllEffects();
  std::shuffle(pool.begin(), pool.end(), rng);
  for (int k = 0; k < count; ++k) {
    s.truth.push_back(pool[static_cast<std::size_t>(k)]);
    Enable(pool[static_cast<std::size_t>(k)], rng, &s);
  }
  if (s.truth.empty()) s.description = "no effect (the rig's stiff default drive loop only)";
  return s;
}

BenchmarkResult RunBenchmark(const BenchmarkOptions& options) {
  BenchmarkResult result;
  result.options = options;
  const std::string config = options.config_path.empty() ? EDSP_DEFAULT_CONFIG : options.config_path;
  const PlatformModel model(LoadConfigFile(config));
  const std::string root = options.keep_dir.empty()
                               ? (std::filesystem::temp_directory_path() / fmt::format("edsp-gap-bench-{}", ::getpid())).string()
                               : options.keep_dir;
  Rng frames(options.seed);
  for (int k = 0; k < options.scenarios; ++k) {
    Progress(options, k, options.scenarios, fmt::format("scenario {}: simulating", k));
    const Scenario s = DrawScenario(options.seed, k);
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
    // The tracker stands somewhere on the floor, turned any way.
    run.tracker.X_TB = Pose::FromVector((Vector6() << Uniform(frames, -3, 3), Uniform(frames, -3, 3),
                                         Uniform(frames, -0.5, 0.5), Uniform(frames, -0.03, 0.03),
                                         Uniform(frames, -0.03, 0.03), Uniform(frames, -3.14, 3.14)).finished());
    run.out_dir = fmt::format("{}/scenario-{:03d}", root, k);
    std::filesystem::create_directories(run.out_dir);
    const auto t0 = std::chrono::steady_clock::now();
    OfflineRunResult sim;
    try {
      sim = RunOffline(config, s.effects, run);
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("scenario {} ({}): {}", k, s.description, e.what()));
    }
    const double simulate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Progress(options, k, options.scenarios, fmt::format("scenario {}: diagnosing", k));
    // Blind: the diagnosis sees the measurement CSV and the nominal model only.
    const Diagnosis d = Diagnose(model, LoadMeasurement(sim.csv_path));
    ScenarioScore score = Score(s, d);
    score.index = k;
    score.simulate_s = simulate_s;
    if (!options.keep_dir.empty()) {
      std::ofstream(run.out_dir + "/diagnosis.json") << ToJson(d).dump(2) << "\n";
      std::ofstream(run.out_dir + "/truth.txt") << s.description << "\n";
    } else {
      std::filesystem::remove_all(run.out_dir);
    }
    result.scores.push_back(score);
  }
  Progress(options, options.scenarios, options.scenarios, "done");
  if (options.keep_dir.empty()) std::filesystem::remove_all(root);

  std::vector<double> shrinks, ratios, seconds;
  for (const ScenarioScore& s : result.scores) {
    const std::size_t n = s.scenario.truth.size();
    seconds.push_back(s.diagnose_s);
    if (n == 0) {
      ++result.clean;
      result.clean_nothing_identified += !s.false_identified;
      continue;
    }
    result.extra_identified += s.false_identified;
    if (n == 1) ++result.single, result.single_top_true += s.top_true;
    if (n == 2) ++result.pairs, result.pairs_both += s.all_found;
    shrinks.push_back(s.shrink);
    ratios.push_back(s.noise_floor_m > 0 ? s.after_rms_m / s.noise_floor_m : 0.0);
  }
  result.median_shrink = Median(shrinks);
  result.median_after_over_noise = Median(ratios);
  result.median_diagnose_s = Median(seconds);
  return result;
}

nlohmann::json ToJson(const BenchmarkResult& r) {
  nlohmann::json j;
  j["seed"] = r.options.seed;
  j["scenarios"] = r.scores.size();
  j["tracker_noise_m"] = r.options.tracker_noise_m;
  auto rate = [](int a, int b) { return b ? static_cast<double>(a) / b : 0.0; };
  j["single_effect"] = {{"scenarios", r.single}, {"top_ranked_true", r.single_top_true},
                        {"rate", rate(r.single_top_true, r.single)}};
  j["two_effects"] = {{"scenarios", r.pairs}, {"both_found", r.pairs_both}, {"rate", rate(r.pairs_both, r.pairs)}};
  j["effect_free"] = {{"scenarios", r.clean}, {"nothing_identified", r.clean_nothing_identified},
                      {"rate", rate(r.clean_nothing_identified, r.clean)}};
  j["with_effects_extra_identified"] = r.extra_identified;  // a false effect identified beside the true ones
  j["median_shrink"] = r.median_shrink;
  j["median_after_over_noise_floor"] = r.median_after_over_noise;
  j["median_diagnose_s"] = r.median_diagnose_s;
  j["results"] = nlohmann::json::array();
  for (const ScenarioScore& s : r.scores) {
    nlohmann::json truth = nlohmann::json::array();
    for (Effect e : s.scenario.truth) truth.push_back(EffectName(e));
    j["results"].push_back({{"index", s.index}, {"truth", truth}, {"description", s.scenario.description},
                            {"found", s.found}, {"top", s.top}, {"conclusion", s.conclusion},
                            {"top_true", s.top_true}, {"all_found", s.all_found},
                            {"false_identified", s.false_identified},
                            {"holdout_before_rms_m", s.before_rms_m}, {"holdout_after_rms_m", s.after_rms_m},
                            {"shrink", s.shrink}, {"noise_floor_rms_m", s.noise_floor_m},
                            {"simulate_s", s.simulate_s}, {"diagnose_s", s.diagnose_s}});
  }
  return j;
}

void PrintBenchmark(const BenchmarkResult& r) {
  std::printf("%-3s %-40s %-40s %8s %8s %7s\n", "#", "truth", "found (ranked)", "before", "after", "shrink");
  for (const ScenarioScore& s : r.scores) {
    std::vector<std::string> truth;
    for (Effect e : s.scenario.truth) truth.push_back(EffectName(e));
    std::printf("%-3d %-40s %-40s %6.1fµm %6.1fµm %6.0f%%\n", s.index,
                (truth.empty() ? std::string("-") : fmt::format("{}", fmt::join(truth, ","))).c_str(),
                (s.found.empty() ? s.top : fmt::format("{}", fmt::join(s.found, ","))).c_str(), s.before_rms_m * 1e6,
                s.after_rms_m * 1e6, 100 * s.shrink);
  }
  std::printf("\nsingle effect: top-ranked true %d/%d; two effects: both found %d/%d; effect-free: nothing "
              "identified %d/%d; a false effect identified beside true ones in %d\nmedian shrink %.0f%%, median after/noise floor %.2f, median diagnosis %.2f s\n",
              r.single_top_true, r.single, r.pairs_both, r.pairs, r.clean_nothing_identified, r.clean, r.extra_identified,
              100 * r.median_shrink, r.median_after_over_noise, r.median_diagnose_s);
}

}  // namespace edsp::gap
