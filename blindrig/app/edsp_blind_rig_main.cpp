// edsp-blind-rig: measurement CSVs from the second, independently written
// virtual rig (docs/diagnosis.md, "The independent rig").
//   edsp-blind-rig --seed S --index K --out data.csv [--truth truth.json] [--config C]
//                  [--rate-hz R] [--noise-m σ] [--no-encoders] [--time-offset-s δ] [--motions Lz,Lx,…]
//                  [--change-time-s T [--change-leg N --change-m S] [--change-tracker x,y,z,r,p,y]]
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/node/runtime.h"
#include "edsp/node/build_paths.h"

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
  std::string config_path = SourcePath("config/huang2021.toml"), out_path, truth_path;
  std::uint64_t seed = 1;
  int index = 1;
  double rate_hz = 0.0, noise_m = -1.0, time_offset_s = 0.0;
  bool no_encoders = false;
  std::vector<std::string> motions;
  double change_time_s = -1.0, change_m = 0.0;
  int change_leg = 0;
  std::vector<double> change_tracker;
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
  app.add_option("--change-time-s", change_time_s,
                 "the rig changes at this time of the session (a step, not an effect)")
      ->check(CLI::NonNegativeNumber);
  CLI::Option* leg =
      app.add_option("--change-leg", change_leg, "the leg whose length steps (1-6)")->check(CLI::Range(1, 6));
  CLI::Option* by = app.add_option("--change-m", change_m, "by how much the leg becomes longer (m; negative: shorter)")
                        ->check(CLI::Range(-0.01, 0.01));
  leg->needs(by);
  by->needs(leg);
  app.add_option("--change-tracker", change_tracker, "the tracker's pose moves by x,y,z (m), roll,pitch,yaw (rad)")
      ->delimiter(',')
      ->expected(6);
  CLI11_PARSE(app, argc, argv);
  if ((change_m != 0.0 || !change_tracker.empty()) && change_time_s < 0.0) {
    throw CLI::ValidationError("--change-time-s", "a change needs its time");
  }

  BlindRigSetup setup = SetupFromConfig(LoadConfigFile(config_path));
  if (!motions.empty()) setup.motions = motions;
  BlindScenario scenario = DrawBlindScenario(seed, index);
  if (rate_hz > 0.0) scenario.tracker.rate_hz = rate_hz;
  if (noise_m >= 0.0) scenario.tracker.noise_m = noise_m;
  if (no_encoders) scenario.tracker.encoders = false;
  scenario.tracker.time_offset_s = time_offset_s;
  scenario.effects.change_time_s = change_time_s;
  if (change_m != 0.0) scenario.effects.change_leg = change_leg - 1, scenario.effects.change_m = change_m;
  for (std::size_t k = 0; k < change_tracker.size(); ++k) {
    scenario.effects.change_tracker(static_cast<Eigen::Index>(k)) = change_tracker[k];
  }
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
                                    {"target_reseat_m", scenario.effects.target_reseat_m}}},
                                  {"change",
                                   {{"time_s", change_time_s},
                                    {"leg", change_m != 0.0 ? nlohmann::json(change_leg) : nlohmann::json(nullptr)},
                                    {"length_m", change_m},
                                    {"tracker", change_tracker}}}};
    WriteFile(truth_path, truth.dump(2) + "\n");
  }
  return 0;
}

}  // namespace
}  // namespace edsp::blind

int main(int argc, char** argv) { return edsp::RunMain("edsp-blind-rig", edsp::blind::Run, argc, argv); }
