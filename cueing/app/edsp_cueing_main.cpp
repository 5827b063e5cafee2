// edsp-cueing: motion cueing (docs/cueing.md).
//   edsp-cueing offline --config FILE --cueing FILE --manoeuvre FILE... [--csv-dir DIR] [--json]
//       each manoeuvre through classical washout at the cueing rate: every
//       setpoint through the kinematics' whole-path check, and what a rider
//       on the commanded platform perceives against the vehicle.

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/cueing/cueing_run.h"
#include "edsp/kinematics/config.h"

namespace edsp {
namespace {

struct OfflineOptions {
  std::string config_path;
  std::string cueing_path;
  std::vector<std::string> manoeuvre_paths;
  std::string csv_dir;
  bool json = false;
};

nlohmann::json ChannelsJson(const PerceptionScore& score) {
  nlohmann::json channels = nlohmann::json::object();
  for (int channel = 0; channel < kCueChannels; ++channel) {
    const ChannelScore& s = score.channels[static_cast<std::size_t>(channel)];
    channels[CueChannelName(channel)] = {{"rms_error", s.rms_error},
                                         {"correlation", s.correlation},
                                         {"delay_s", s.delay_s},
                                         {"in_thresholds", s.in_thresholds}};
  }
  return channels;
}

nlohmann::json RunJson(const Manoeuvre& manoeuvre, const CueingRun& run) {
  nlohmann::json out = {{"name", manoeuvre.name},
                        {"file", manoeuvre.origin},
                        {"duration_s", manoeuvre.duration_s},
                        {"perception_error", run.score.overall},
                        {"channels", ChannelsJson(run.score)},
                        {"limit_violations", run.path.ok() ? 0 : 1},
                        {"peak_stroke_used", run.peak_stroke_used},
                        {"peak_leg_speed_m_s", run.path.peak_leg_speed_m_s},
                        {"peak_leg_accel_m_s2", run.path.peak_leg_accel_m_s2}};
  if (!run.path.ok()) out["violation"] = run.path.Describe();
  return out;
}

void PrintRow(const Manoeuvre& manoeuvre, const CueingRun& run) {
  std::string channels;
  for (int channel = 0; channel < kCueChannels; ++channel) {
    channels += fmt::format(" {:6.2f}", run.score.channels[static_cast<std::size_t>(channel)].in_thresholds);
  }
  std::printf("%-22s %6.2f %s %6.0f%%  %s\n", manoeuvre.name.c_str(), run.score.overall, channels.c_str(),
              100.0 * run.peak_stroke_used, run.path.ok() ? "ok" : run.path.Describe().c_str());
}

int RunOffline(const OfflineOptions& options) {
  const PlatformModel model(LoadConfigFile(options.config_path));
  const CueingConfig config = LoadCueingConfig(options.cueing_path);
  std::vector<Manoeuvre> manoeuvres;
  for (const std::string& path : options.manoeuvre_paths) manoeuvres.push_back(LoadManoeuvre(path));
  if (!options.csv_dir.empty()) std::filesystem::create_directories(options.csv_dir);
  nlohmann::json runs = nlohmann::json::array();
  double error_sum = 0.0;
  int violations = 0;
  if (!options.json) {
    std::printf("classical washout: perceived error in thresholds (overall, then fx fy fz wx wy wz), stroke used\n");
  }
  for (const Manoeuvre& manoeuvre : manoeuvres) {
    const CueingRun run = RunClassicalWashout(model, config, manoeuvre);
    error_sum += run.score.overall;
    violations += run.path.ok() ? 0 : 1;
    if (!options.csv_dir.empty()) {
      const std::string path = (std::filesystem::path(options.csv_dir) / (manoeuvre.name + ".csv")).string();
      std::ofstream(path) << CueingRunCsv(run);
    }
    if (options.json)
      runs.push_back(RunJson(manoeuvre, run));
    else
      PrintRow(manoeuvre, run);
  }
  const double mean_error = error_sum / static_cast<double>(manoeuvres.size());
  if (options.json) {
    const nlohmann::json out = {{"algorithm", "classical_washout"},
                                {"manoeuvres", runs},
                                {"perception_error", mean_error},
                                {"limit_violations", violations}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("mean perception error %.3f thresholds; %d of %zu manoeuvres leave a limit\n", mean_error, violations,
                manoeuvres.size());
  }
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-cueing: vehicle motion in, platform motion out (docs/cueing.md)"};
  app.require_subcommand(1);
  edsp::OfflineOptions offline;
  CLI::App* offline_command =
      app.add_subcommand("offline", "manoeuvres through classical washout, checked and scored offline");
  offline_command->add_option("--config", offline.config_path, "platform config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command->add_option("--cueing", offline.cueing_path, "cueing config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command->add_option("--manoeuvre", offline.manoeuvre_paths, "manoeuvre file(s) (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command->add_option("--csv-dir", offline.csv_dir, "write <manoeuvre>.csv per manoeuvre here");
  offline_command->add_flag("--json", offline.json, "JSON on stdout");
  CLI11_PARSE(app, argc, argv);
  try {
    return edsp::RunOffline(offline);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-cueing: %s\n", e.what());
    return 1;
  }
}
