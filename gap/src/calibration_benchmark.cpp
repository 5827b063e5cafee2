#include "edsp/gap/calibration_benchmark.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/gap/blind_closed_loop.h"
#include "edsp/gap/closed_loop.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/report.h"
#include "edsp/gap/rig_scenarios.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "draws.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {

namespace {

// The benchmark's motions (benchmark.cpp): five stops, half a second at
// each, a quarter metre and half a radian per second at most.
OfflineRunOptions RunOptions(const CalibrationBenchmarkOptions& o, std::mt19937_64& stands, int rig) {
  OfflineRunOptions run;
  run.paper.stops = 5;
  run.paper.dwell_s = 0.5;
  run.paper.max_speed_m_s = 0.25;
  run.paper.max_speed_rad_s = 0.5;
  run.tracker.noise_sigma_m = o.tracker_noise_m;
  run.tracker.rate_hz = o.tracker_rate_hz;
  run.tracker.seed = o.seed * 7919 + static_cast<std::uint64_t>(rig);
  run.tracker.X_TB = DrawTrackerStand(stands);
  return run;
}

bool MeetsTarget(const DesignScore& s, double floor_m) {
  const bool small = s.after_rms_m <= kCalibrationTargetFloorRatio * floor_m ||
                     Shrink(s.before_rms_m, s.after_rms_m) >= kCalibrationTargetShrink;
  return small && s.after_max_m <= s.before_max_m;
}

// A rig under test, whichever generator made it: its fit run of some
// motions (the CSV and the motions' length), and the closed loop of a saved
// model on the held-out motions.
struct RigRuns {
  std::function<std::pair<std::string, double>(const std::vector<std::string>& motions, const std::string& dir)> fit;
  std::function<MotionCheck(const nlohmann::json& saved, const std::string& dir)> closed_loop;
};

// edsp's rig: edsp-sim rig's offline stack.
RigRuns OnEdspRig(const PlatformModel& model, const std::string& config, const Scenario& rig,
                  const OfflineRunOptions& run, const std::vector<std::string>& held_out) {
  return {[&, run](const std::vector<std::string>& motions, const std::string& dir) {
            OfflineRunOptions fit_run = run;
            fit_run.motions = motions;
            fit_run.out_dir = dir + "/fit";
            const OfflineRunResult fit = RunOffline(config, rig.effects, fit_run);
            return std::make_pair(fit.csv_path, fit.duration_s);
          },
          [&, run](const nlohmann::json& saved, const std::string& dir) {
            return MeasureClosedLoop(model, config, rig.effects, run, saved, held_out, dir);
          }};
}

// The blind rig (blindrig/), at the benchmark's speeds and dwells: its own
// motions, and edsp's planned ones (the designed set) as samples.
RigRuns OnBlindRig(const PlatformModel& model, const PlatformConfig& config, const blind::BlindScenario& rig,
                   const PaperMotionOptions& paper, const std::vector<std::string>& held_out) {
  blind::BlindRigSetup setup = blind::SetupFromConfig(config);
  setup.limits.stops = paper.stops;
  setup.limits.dwell_s = paper.dwell_s;
  setup.limits.linear_speed_m_s = paper.max_speed_m_s;
  setup.limits.angular_speed_rad_s = paper.max_speed_rad_s;
  return {[&, setup, paper](const std::vector<std::string>& motions, const std::string& dir) {
            const BlindRun fit = RunBlindRig(WithMotions(setup, model, paper, motions), rig, dir + "/fit.csv");
            return std::make_pair(fit.csv_path, fit.duration_s);
          },
          [&, setup, paper](const nlohmann::json& saved, const std::string& dir) {
            return MeasureBlindClosedLoop(model, WithMotions(setup, model, paper, held_out), rig, saved, dir);
          }};
}

// One design on one rig: fit, diagnose blind, close the loop on held-out motions.
DesignScore ScoreDesign(const PlatformModel& model, const RigRuns& rig, const MotionDesign& design,
                        const CalibrationBenchmarkOptions& o, const std::string& dir, double floor_m) {
  DesignScore s;
  s.design = design.name;
  try {
    const auto [fit_csv, fit_duration_s] = rig.fit(design.motions, dir);
    s.fit_duration_s = fit_duration_s;
    const Diagnosis d = Diagnose(model, LoadMeasurement(fit_csv));
    s.conclusion = ConclusionName(d.conclusion);
    const nlohmann::json saved = ModelJson(d);
    const nlohmann::json applied = AppliedModelJson(saved, false);  // kept: a range over a temporary's member dangles
    for (const auto& e : applied["effects"]) s.applied.push_back(e["name"].get<std::string>());
    if (!o.keep_dir.empty()) std::ofstream(dir + "/diagnosis.json") << ToJson(d).dump(2) << "\n";
    const MotionCheck loop = rig.closed_loop(saved, dir);
    s.before_rms_m = loop.before.rms_m, s.before_max_m = loop.before.max_m;
    s.after_rms_m = loop.after.rms_m, s.after_max_m = loop.after.max_m;
    s.predicted_rms_m = loop.predicted ? loop.predicted->rms_m : 0.0;
    s.met = MeetsTarget(s, floor_m);
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return s;
}

void Progress(const CalibrationBenchmarkOptions& o, int done, const std::string& what) {
  if (!o.progress) return;
  std::fprintf(stderr, "\rrig %d/%d %-50.50s", done, o.rigs, what.c_str());
  if (done == o.rigs) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

void Tally(CalibrationBenchmarkResult* r) {
  const std::size_t designs = r->options.designs.size();
  r->met.assign(designs, 0);
  r->median_after_over_floor.assign(designs, 0.0);
  r->median_shrink.assign(designs, 0.0);
  for (std::size_t k = 0; k < designs; ++k) {
    std::vector<double> ratios, shrinks;
    for (const RigScore& rig : r->rigs) {
      const DesignScore& s = rig.designs[k];
      r->met[k] += s.met;
      if (!s.error.empty()) continue;
      ratios.push_back(s.after_rms_m / rig.noise_floor_m);
      shrinks.push_back(Shrink(s.before_rms_m, s.after_rms_m));
    }
    r->median_after_over_floor[k] = Median(ratios);
    r->median_shrink[k] = Median(shrinks);
  }
  if (designs < 2) return;
  for (const RigScore& rig : r->rigs) {
    const DesignScore &a = rig.designs[0], &b = rig.designs[1];
    r->first_as_good += a.error.empty() && (!b.error.empty() || a.after_rms_m <= 1.1 * b.after_rms_m);
  }
}

}  // namespace

CalibrationBenchmarkResult RunCalibrationBenchmark(const CalibrationBenchmarkOptions& options) {
  if (options.designs.empty()) throw std::invalid_argument("calibration benchmark: no motion design to score");
  if (options.held_out.empty()) throw std::invalid_argument("calibration benchmark: no held-out motions");
  CalibrationBenchmarkResult result;
  result.options = options;
  const std::string config = options.config_path.empty() ? SourcePath("config/huang2021.toml") : options.config_path;
  const PlatformConfig platform = LoadConfigFile(config);
  const PlatformModel model(platform);
  result.rated_payload_kg = WholeRigRatedPayload(model);
  const std::string root =
      options.keep_dir.empty()
          ? (std::filesystem::temp_directory_path() / fmt::format("edsp-gap-calibration-bench-{}", ::getpid())).string()
          : options.keep_dir;
  std::mt19937_64 stands(options.seed);
  const bool blind_rig = options.generator == Generator::kBlind;
  for (int k = 0; k < options.rigs; ++k) {
    RigScore score;
    score.index = k;
    score.rated_payload_kg = result.rated_payload_kg;
    score.noise_floor_m = std::sqrt(3.0) * options.tracker_noise_m;
    // Both draws are made whichever rig runs: the tracker stands of the
    // rigs after this one stay the same draws.
    const Scenario edsp_rig = DrawWholeRig(options.seed, k, result.rated_payload_kg);
    const OfflineRunOptions run = RunOptions(options, stands, k);
    blind::BlindScenario blind_rig_drawn = blind::DrawBlindWholeRig(options.seed, k, result.rated_payload_kg);
    blind_rig_drawn.tracker.noise_m = options.tracker_noise_m;
    blind_rig_drawn.tracker.rate_hz = options.tracker_rate_hz;
    score.description = blind_rig ? blind_rig_drawn.description : edsp_rig.description;
    score.payload_kg = blind_rig ? blind_rig_drawn.effects.mass_kg : edsp_rig.effects.compliance.mass_kg;
    const RigRuns rig = blind_rig ? OnBlindRig(model, platform, blind_rig_drawn, run.paper, options.held_out)
                                  : OnEdspRig(model, config, edsp_rig, run, options.held_out);
    for (const MotionDesign& design : options.designs) {
      Progress(options, k, fmt::format("rig {}: {}", k, design.name));
      const std::string dir = fmt::format("{}/rig-{:03d}/{}", root, k, design.name);
      std::filesystem::create_directories(dir);
      score.designs.push_back(ScoreDesign(model, rig, design, options, dir, score.noise_floor_m));
    }
    result.rigs.push_back(score);
  }
  Progress(options, options.rigs, "done");
  if (options.keep_dir.empty()) std::filesystem::remove_all(root);
  Tally(&result);
  return result;
}

nlohmann::json ToJson(const CalibrationBenchmarkResult& r) {
  nlohmann::json j;
  j["mode"] = "calibration";
  j["generator"] = GeneratorName(r.options.generator);
  j["seed"] = r.options.seed;
  j["tracker_noise_m"] = r.options.tracker_noise_m;
  j["tracker_rate_hz"] = r.options.tracker_rate_hz;
  j["held_out"] = r.options.held_out;
  j["rated_payload_kg"] = r.rated_payload_kg;
  j["target"] = {{"after_over_floor_at_most", kCalibrationTargetFloorRatio},
                 {"or_shrink_at_least", kCalibrationTargetShrink},
                 {"and_max_no_larger", true}};
  j["designs"] = nlohmann::json::array();
  for (std::size_t k = 0; k < r.options.designs.size(); ++k) {
    const int rigs = static_cast<int>(r.rigs.size());
    j["designs"].push_back({{"name", r.options.designs[k].name},
                            {"motions", r.options.designs[k].motions},
                            {"met", r.met[k]},
                            {"rigs", rigs},
                            {"met_rate", rigs ? static_cast<double>(r.met[k]) / rigs : 0.0},
                            {"median_after_over_floor", r.median_after_over_floor[k]},
                            {"median_shrink", r.median_shrink[k]}});
  }
  j["first_design_as_good"] = r.first_as_good;
  j["rigs"] = nlohmann::json::array();
  for (const RigScore& rig : r.rigs) {
    nlohmann::json jr = {{"index", rig.index},
                         {"description", rig.description},
                         {"payload_kg", rig.payload_kg},
                         {"noise_floor_m", rig.noise_floor_m}};
    for (const DesignScore& s : rig.designs) {
      nlohmann::json js = {
          {"fit_duration_s", s.fit_duration_s}, {"conclusion", s.conclusion},           {"applied", s.applied},
          {"before_rms_m", s.before_rms_m},     {"before_max_m", s.before_max_m},       {"after_rms_m", s.after_rms_m},
          {"after_max_m", s.after_max_m},       {"predicted_rms_m", s.predicted_rms_m}, {"met", s.met}};
      if (!s.error.empty()) js["error"] = s.error;
      jr[s.design] = js;
    }
    j["rigs"].push_back(jr);
  }
  return j;
}

void PrintCalibrationBenchmark(const CalibrationBenchmarkResult& r) {
  std::printf("calibration on %zu whole rigs of %s (seed %llu, payloads 500–%.0f kg), held out: %s\n", r.rigs.size(),
              r.options.generator == Generator::kBlind ? "the blind rig" : "edsp's rig",
              static_cast<unsigned long long>(r.options.seed), r.rated_payload_kg,
              fmt::format("{}", fmt::join(r.options.held_out, ",")).c_str());
  std::printf("%-4s %-58s", "rig", "");
  for (const MotionDesign& d : r.options.designs) std::printf(" %-28s", d.name.c_str());
  std::printf("\n");
  for (const RigScore& rig : r.rigs) {
    std::printf("%-4d %-58.58s", rig.index, rig.description.c_str());
    for (const DesignScore& s : rig.designs) {
      const std::string cell = s.error.empty() ? fmt::format("{:.1f} → {:.1f} µm {}", s.before_rms_m * 1e6,
                                                             s.after_rms_m * 1e6, s.met ? "met" : "NOT met")
                                               : "error";
      std::printf(" %-28s", cell.c_str());
    }
    std::printf("\n");
  }
  for (std::size_t k = 0; k < r.options.designs.size(); ++k) {
    std::printf("%s: target met on %d of %zu rigs; median after %.2f× the floor, shrink %.0f%%\n",
                r.options.designs[k].name.c_str(), r.met[k], r.rigs.size(), r.median_after_over_floor[k],
                100 * r.median_shrink[k]);
  }
}

}  // namespace edsp::gap
