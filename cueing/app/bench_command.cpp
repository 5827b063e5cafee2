#include "bench_command.h"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/manoeuvre_variants.h"
#include "edsp/cueing/cueing_soak.h"
#include "edsp/cueing/omct.h"
#include "edsp/cueing/platform_motion.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_effects.h"
#include "perception_json.h"

namespace edsp {
namespace {

// One algorithm's figures for the bench: its perception error per
// manoeuvre (commanded, and on the rig's real motion with effects), the
// manoeuvres and soak setpoints that leave a limit, and its step's time.
struct AlgorithmFigures {
  nlohmann::json json;
  double commanded = 0.0, real = 0.0;  // the means over the manoeuvres
  double variants = 0.0;               // the mean over their variants, commanded
};

// The mean perception error, commanded, over every manoeuvre's variants.
double VariantsError(const BenchOptions& options, CueingAlgorithm algorithm, const PlatformModel& model,
                     const CueingConfig& config) {
  double sum = 0.0;
  int count = 0;
  for (const std::string& path : options.offline.manoeuvre_paths) {
    for (const Manoeuvre& variant : ManoeuvreVariants(LoadManoeuvre(path), options.variants, options.variant_seed)) {
      sum += RunCueing(model, config, algorithm, variant).score.overall;
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

AlgorithmFigures BenchAlgorithm(const BenchOptions& options, CueingAlgorithm algorithm, const PlatformConfig& nominal,
                                const PlatformModel& model, const CueingConfig& config,
                                const std::optional<RigEffects>& effects) {
  nlohmann::json commanded = nlohmann::json::object(), real = nlohmann::json::object();
  double sum = 0.0, real_sum = 0.0;
  std::int64_t violations = 0;
  for (const std::string& path : options.offline.manoeuvre_paths) {
    const Manoeuvre manoeuvre = LoadManoeuvre(path);
    if (manoeuvre.name == "overall") {
      throw std::runtime_error(fmt::format("{}: a manoeuvre named \"overall\" would hide the bench's mean", path));
    }
    const CueingRun run = RunCueing(model, config, algorithm, manoeuvre);
    commanded[manoeuvre.name] = run.score.overall;
    sum += run.score.overall;
    violations += run.path.ok() ? 0 : 1;
    if (effects) {
      const double on_rig = ScoreOnTheRig(nominal, *effects, config, run).overall;
      real[manoeuvre.name] = on_rig;
      real_sum += on_rig;
    }
  }
  const double count = static_cast<double>(options.offline.manoeuvre_paths.size());
  AlgorithmFigures figures;
  figures.commanded = sum / count;
  figures.real = effects ? real_sum / count : figures.commanded;
  commanded["overall"] = figures.commanded;
  if (effects) real["overall"] = figures.real;
  figures.variants = VariantsError(options, algorithm, model, config);
  const CueingSoak soak = SoakCueing(model, config, algorithm, RandomVehicleParameters{}, options.cycles, options.seed);
  figures.json = {
      {"perception_error", commanded},
      {"limit_violations", violations + soak.refused_setpoints},
      {"soak",
       {{"cycles", soak.cycles},
        {"seed", options.seed},
        {"refused_setpoints", soak.refused_setpoints},
        {"first_refusal", soak.first_refusal},
        {"peak_stroke_used", soak.peak_stroke_used},
        {"unconverged_solves", soak.unconverged_solves}}},
      {"solve_ms",
       {{"p50", soak.solve_p50_us * 1e-3}, {"p99", soak.solve_p99_us * 1e-3}, {"max", soak.solve_max_us * 1e-3}}},
      {"step_ms", {{"p50", soak.step_p50_us * 1e-3}, {"p99", soak.step_p99_us * 1e-3}}}};
  if (algorithm == CueingAlgorithm::kModelPredictive)
    figures.json["solve_period_ms"] = config.mpc.horizon.solve_period_s * 1e3;
  if (effects) figures.json["perception_error_real"] = real;
  if (options.variants > 0) {
    figures.json["perception_error_variants"] = {
        {"overall", figures.variants}, {"variants_per_manoeuvre", options.variants}, {"seed", options.variant_seed}};
  }
  if (!options.offline.json) {
    std::printf("%s: mean perception error %.3f thresholds", CueingAlgorithmName(algorithm), figures.commanded);
    if (effects) std::printf(" (%.3f on the rig)", figures.real);
    if (options.variants > 0) std::printf(" (%.3f over their variants)", figures.variants);
    std::printf("; manoeuvres leaving a limit %lld\n", static_cast<long long>(violations));
    std::printf(
        "  soak: %lld cycles of random vehicle motion (seed %llu), %lld setpoints refused%s%s; stroke used %.0f%%\n",
        static_cast<long long>(soak.cycles), static_cast<unsigned long long>(options.seed),
        static_cast<long long>(soak.refused_setpoints), soak.first_refusal.empty() ? "" : ", the first ",
        soak.first_refusal.c_str(), 100.0 * soak.peak_stroke_used);
    std::printf("  solve: p50 %.3f ms, p99 %.3f ms, max %.3f ms; %lld stopped at the iteration limit\n",
                soak.solve_p50_us * 1e-3, soak.solve_p99_us * 1e-3, soak.solve_max_us * 1e-3,
                static_cast<long long>(soak.unconverged_solves));
  }
  return figures;
}

// The figures of docs/cueing.md's "Bench", for every algorithm, and the
// model-predictive cueing's perception error over classical washout's (on
// the rig's real motion when its effects are given). The delay needs the
// live group: null here, with the reason.

}  // namespace

int RunBench(const BenchOptions& options) {
  const PlatformConfig nominal = LoadConfigFile(options.offline.config_path);
  const PlatformModel model(nominal);
  const CueingConfig config = LoadCueingConfig(options.offline.cueing_path);
  std::optional<RigEffects> effects;
  if (!options.offline.rig_effects_path.empty()) effects = LoadRigEffects(options.offline.rig_effects_path);
  nlohmann::json algorithms = nlohmann::json::object();
  std::map<CueingAlgorithm, AlgorithmFigures> figures;
  for (CueingAlgorithm algorithm : kCueingAlgorithms) {
    figures[algorithm] = BenchAlgorithm(options, algorithm, nominal, model, config, effects);
    algorithms[CueingAlgorithmName(algorithm)] = figures[algorithm].json;
  }
  const double ratio =
      figures[CueingAlgorithm::kModelPredictive].real / figures[CueingAlgorithm::kClassicalWashout].real;
  nlohmann::json out = {
      {"algorithms", algorithms},
      {"ratio", ratio},
      {"ratio_of", effects ? "perception_error_real" : "perception_error"},
      {"ratio_variants", options.variants > 0 ? nlohmann::json(figures[CueingAlgorithm::kModelPredictive].variants /
                                                               figures[CueingAlgorithm::kClassicalWashout].variants)
                                              : nlohmann::json(nullptr)},
      {"omct", OmctJson(RunOmct(model, config))},
      {"delay_p99_ms", nullptr},
      {"delay_why_null", "measured on the live group: edsp-bench-cueing-live"}};
  if (options.offline.json) {
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("ratio (mpc over classical washout, %s): %.3f\n", effects ? "on the rig" : "commanded", ratio);
  if (options.variants > 0) {
    std::printf("ratio over the variants (commanded): %.3f\n", out["ratio_variants"].get<double>());
  }
  return 0;
}

}  // namespace edsp
