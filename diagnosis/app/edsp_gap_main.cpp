// edsp-gap: diagnose the sim-to-real gap (docs/diagnosis.md).
//   edsp-gap diagnose --config C --data D [--data D2 …] [--json] [--save-model M] [--report DIR]
//   edsp-gap evaluate --config C --model M --data T [--json]
//   edsp-gap compare --config C --before B --after A [--model M [--apply-ambiguous]] [--plot DIR] [--json]
//   edsp-gap benchmark --scenarios N --seed S [--generator rig|blind] [--motions Lz,…] [--json] [--noise-m 5e-6] [--keep DIR]
//                      [--closed-loop-motions Ly,Rx,M9|none]
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/benchmark.h"
#include "edsp/diagnosis/calibration_check.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/runtime.h"

namespace edsp::gap {
namespace {

MeasurementData LoadAll(const std::vector<std::string>& paths) {
  MeasurementData data;
  for (const std::string& path : paths) AppendMeasurement(&data, LoadMeasurement(path));
  return data;
}

nlohmann::json LoadModelFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MeasurementError(path + ": cannot open");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw MeasurementError(fmt::format("{}: not JSON at byte {}: {}", path, e.byte, e.what()));
  }
}

void PrintText(const Diagnosis& d) {
  std::printf("gap before any effect: %.1f µm RMS, %.1f µm max over %d samples in %zu runs\n",
              d.gap.overall.rms_m * 1e6, d.gap.overall.max_m * 1e6, d.samples, d.runs.size());
  std::printf("%s\n\n", d.gap.where.c_str());
  std::printf("%-4s %-20s %-11s %9s %9s  %s\n", "rank", "effect", "verdict", "explained", "cv gain", "with");
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    const EffectResult& r = d.effects[k];
    std::printf("%-4zu %-20s %-11s %8.1f%% %8.1f%%  %s\n", k + 1, EffectName(r.effect), r.verdict.c_str(),
                100 * r.explained_fraction, 100 * r.cv_gain, fmt::format("{}", fmt::join(r.ambiguous_with, ", ")).c_str());
  }
  std::printf("\nconclusion: %s\n", d.conclusion.c_str());
  std::printf("held-out runs: before %.1f µm RMS, after %.1f µm RMS, shrink %.0f%% (noise floor %.1f µm)\n",
              d.holdout_before.rms_m * 1e6, d.holdout_after.rms_m * 1e6, 100 * d.shrink, d.noise_floor_rms_m * 1e6);
  std::printf("left: %s\n", d.unexplained_note.c_str());
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-gap: where the model and the measured platform part, which effect causes it, how far "
               "the gap shrinks once it is modelled"};
  app.require_subcommand(1);
  std::string config_path, model_path, report_dir, keep_dir;
  std::vector<std::string> data_paths;
  bool json = false;
  DiagnoseOptions options;

  CLI::App* diagnose = app.add_subcommand("diagnose", "diagnose measured data against the config's model");
  diagnose->add_option("--config", config_path, "platform config (TOML)")->required();
  diagnose->add_option("--data", data_paths, "measurement CSV (interfaces.md §3) or edsp LCM log; repeatable")->required();
  diagnose->add_flag("--json", json, "print the JSON report (interfaces.md §4)");
  diagnose->add_option("--save-model", model_path, "write the selected effects for `evaluate`");
  diagnose->add_option("--report", report_dir, "write report.md with PNG plots here");
  diagnose->add_option("--max-rate-hz", options.max_rate_hz, "thin each run to this rate")->check(CLI::Range(1.0, 10000.0));
  CLI::Option* thermal_tau =
      diagnose->add_option("--thermal-time-constant-s", options.design.thermal_time_constant_s,
                           "the screws' cooling time, fixed (default: estimated when thermal drift is found)")
          ->check(CLI::Range(1.0, 1e6));

  CLI::App* evaluate = app.add_subcommand("evaluate", "apply a saved model to data it has never seen");
  evaluate->add_option("--config", config_path, "platform config (TOML)")->required();
  evaluate->add_option("--model", model_path, "model saved by diagnose --save-model")->required();
  evaluate->add_option("--data", data_paths, "measurement CSV or edsp LCM log; repeatable")->required();
  evaluate->add_flag("--json", json, "print JSON");

  std::vector<std::string> before_paths, after_paths;
  std::string plot_dir;
  CLI::App* compare = app.add_subcommand(
      "compare", "the same motions measured without and with a calibration: point A's error per motion");
  compare->add_option("--config", config_path, "platform config (TOML)")->required();
  compare->add_option("--before", before_paths, "measurement without the calibration (CSV or LCM log); repeatable")
      ->required();
  compare->add_option("--after", after_paths, "the same motions with the calibration applied; repeatable")->required();
  compare->add_option("--model", model_path, "the calibration's model: its prediction from --before, beside");
  bool apply_ambiguous = false;
  compare->add_flag("--apply-ambiguous", apply_ambiguous,
                    "the controller applied the model's ambiguous effects too (predict with them)");
  compare->add_option("--plot", plot_dir, "write calibration.png (and its data and gnuplot script) here");
  compare->add_flag("--json", json, "print JSON");

  BenchmarkOptions bench;
  CLI::App* benchmark = app.add_subcommand("benchmark", "score the diagnosis blind on virtual-rig scenarios");
  benchmark->add_option("--scenarios", bench.scenarios, "how many")->check(CLI::Range(1, 100000));
  benchmark->add_option("--seed", bench.seed, "scenario draw seed");
  benchmark->add_option("--config", bench.config_path, "nominal platform config");
  benchmark->add_option("--noise-m", bench.tracker_noise_m, "tracker noise, 1-σ per axis")->check(CLI::Range(0.0, 1e-3));
  benchmark->add_option("--generator", bench.generator,
                        "rig: edsp's own virtual rig; blind: the independently written rig (blindrig/), "
                        "out-of-vocabulary scenarios and its own tracker draws")
      ->check(CLI::IsMember({"rig", "blind"}));
  benchmark->add_option("--motions", bench.motions, "motions of every scenario, comma-separated")->delimiter(',');
  benchmark->add_option("--closed-loop-motions", bench.closed_loop_motions,
                        "rig generator: motions no fit saw, run without and with the model applied (\"none\": skip)")
      ->delimiter(',');
  benchmark->add_option("--keep", keep_dir, "keep each scenario's data and report here");
  benchmark->add_flag("--json", json, "print JSON");
  CLI11_PARSE(app, argc, argv);
  if (thermal_tau->count() > 0) options.thermal_time_constants_s.clear();

  if (*benchmark) {
    bench.keep_dir = keep_dir;
    if (bench.closed_loop_motions == std::vector<std::string>{"none"}) bench.closed_loop_motions.clear();
    bench.progress = !json || isatty(fileno(stderr));
    const BenchmarkResult result = RunBenchmark(bench);
    if (json) std::printf("%s\n", ToJson(result).dump(2).c_str());
    else PrintBenchmark(result);
    return 0;
  }
  const PlatformModel model(LoadConfigFile(config_path));
  if (*compare) {
    const bool predicted = !model_path.empty();
    // Predicted from what the kinematics applied: identified effects, the
    // ambiguous ones only with --apply-ambiguous.
    const Evaluation without =
        Evaluate(model, LoadAll(before_paths),
                 predicted ? AppliedModelJson(LoadModelFile(model_path), apply_ambiguous) : EmptyModelJson(),
                 predicted ? model_path : "no model");
    const Evaluation with = Evaluate(model, LoadAll(after_paths), EmptyModelJson(), "no model");
    const CalibrationCheck check = CheckCalibration(without, with, predicted);
    if (!plot_dir.empty()) {
      std::filesystem::create_directories(plot_dir);
      const std::string png = WriteCheckPlot(check, plot_dir);
      if (!json) std::printf("%s\n", png.empty() ? "gnuplot wrote no plot" : png.c_str());
    }
    if (json) std::printf("%s\n", ToJson(check).dump(2).c_str());
    else std::printf("%s", CheckTable(check).c_str());
    return 0;
  }
  const MeasurementData data = LoadAll(data_paths);
  if (*evaluate) {
    const Evaluation ev = Evaluate(model, data, LoadModelFile(model_path), model_path);
    if (json) {
      std::printf("%s\n", ToJson(ev).dump(2).c_str());
    } else {
      std::printf("before %.1f µm RMS (%.1f max), after %.1f µm RMS (%.1f max), shrink %.0f%%\n", ev.before.rms_m * 1e6,
                  ev.before.max_m * 1e6, ev.after.rms_m * 1e6, ev.after.max_m * 1e6, 100 * ev.shrink);
    }
    return 0;
  }
  const Diagnosis d = Diagnose(model, data, options);
  if (!model_path.empty()) {
    std::ofstream out(model_path);
    out << ModelJson(d).dump(2) << "\n";
    if (!out) throw std::runtime_error(model_path + ": cannot write the model");
  }
  if (!report_dir.empty()) WriteReport(d, report_dir);
  if (json) std::printf("%s\n", ToJson(d).dump(2).c_str());
  else PrintText(d);
  return 0;
}

}  // namespace
}  // namespace edsp::gap

int main(int argc, char** argv) { return edsp::RunMain("edsp-gap", edsp::gap::Run, argc, argv); }
