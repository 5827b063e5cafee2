// edsp-blind-rig: measurement CSVs from the second, independently written
// virtual rig (docs/diagnosis.md, "The independent rig").
//   edsp-blind-rig --seed S --index K --out data.csv [--truth truth.json] [--config C]
//                  [--rate-hz R] [--noise-m σ] [--no-encoders] [--time-offset-s δ] [--motions Lz,Lx,…]
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/node/runtime.h"

namespace edsp::blind {
namespace {

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path + ": cannot write");
}

int Run(int argc, char** argv) {
  CLI::App app{
      "edsp-blind-rig: measurement CSVs (interfaces.md §3) of a scenario drawn on an independently "
      "written virtual rig, the truth kept apart"};
  std::string config_path = EDSP_DEFAULT_CONFIG, out_path, truth_path;
  std::uint64_t seed = 1;
  int index = 1;
  double rate_hz = 0.0, noise_m = -1.0, time_offset_s = 0.0;
  bool no_encoders = false;
  std::vector<std::string> motions;
  app.add_option("--config", config_path, "nominal platform config")->check(CLI::ExistingFile);
  app.add_option("--seed", seed, "scenario seed");
  app.add_option("--index", index, "scenario index: %5 = 0 none, 1-2 single, 3 pair, 4 out of vocabulary")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--out", out_path, "measurement CSV to write")->required();
  app.add_option("--truth", truth_path, "JSON of what the scenario holds (kept from the diagnosis)");
  app.add_option("--rate-hz", rate_hz, "tracker rate instead of the drawn one")->check(CLI::Range(1.0, 10000.0));
  app.add_option("--noise-m", noise_m, "tracker 1-σ per axis instead of the drawn one")->check(CLI::Range(0.0, 1e-3));
  app.add_flag("--no-encoders", no_encoders, "leave out the leg_enc_* columns");
  app.add_option("--time-offset-s", time_offset_s,
                 "tracker readings δ late (its clock ahead of the controller's): a row stamped t reads instant t - δ")
      ->check(CLI::Range(-0.1, 0.1));
  app.add_option("--motions", motions, "motions, comma-separated")->delimiter(',');
  CLI11_PARSE(app, argc, argv);

  BlindRigSetup setup = SetupFromConfig(LoadConfigFile(config_path));
  if (!motions.empty()) setup.motions = motions;
  BlindScenario scenario = DrawBlindScenario(seed, index);
  if (rate_hz > 0.0) scenario.tracker.rate_hz = rate_hz;
  if (noise_m >= 0.0) scenario.tracker.noise_m = noise_m;
  if (no_encoders) scenario.tracker.encoders = false;
  scenario.tracker.time_offset_s = time_offset_s;
  WriteFile(out_path, GenerateMeasurementCsv(setup, scenario.effects, scenario.tracker));
  if (!truth_path.empty()) {
    const nlohmann::json truth = {{"kind", scenario.kind},
                                  {"truth", scenario.truth},
                                  {"description", scenario.description},
                                  {"tracker",
                                   {{"rate_hz", scenario.tracker.rate_hz},
                                    {"noise_m", scenario.tracker.noise_m},
                                    {"encoders", scenario.tracker.encoders},
                                    {"time_offset_s", scenario.tracker.time_offset_s},
                                    {"clock_drift", scenario.effects.clock_drift},
                                    {"target_reseat_m", scenario.effects.target_reseat_m}}}};
    WriteFile(truth_path, truth.dump(2) + "\n");
  }
  return 0;
}

}  // namespace
}  // namespace edsp::blind

int main(int argc, char** argv) { return edsp::RunMain("edsp-blind-rig", edsp::blind::Run, argc, argv); }
