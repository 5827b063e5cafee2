#include "offline_command.h"

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

#include "edsp/cueing/cueing_plot.h"
#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/omct.h"
#include "edsp/cueing/platform_motion.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/sim/played_poses.h"
#include "perception_json.h"

namespace edsp {
namespace {

CueingAlgorithm AlgorithmNamed(const std::string& name) {
  const std::optional<CueingAlgorithm> algorithm = CueingAlgorithmFromName(name);
  if (!algorithm) {
    throw std::invalid_argument(fmt::format("--algorithm {}: not one of classical_washout, mpc", name));
  }
  return *algorithm;
}

nlohmann::json RunJson(const Manoeuvre& manoeuvre, const CueingRun& run, const std::optional<PerceptionScore>& real) {
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
  if (real) out["real"] = {{"perception_error", real->overall}, {"channels", ChannelsJson(*real)}};
  return out;
}

void PrintRow(const Manoeuvre& manoeuvre, const CueingRun& run, const std::optional<PerceptionScore>& real) {
  std::string channels;
  for (int channel = 0; channel < kCueChannels; ++channel) {
    channels += fmt::format(" {:6.2f}", run.score.channels[static_cast<std::size_t>(channel)].in_thresholds);
  }
  const std::string on_rig = real ? fmt::format(" {:8.2f}", real->overall) : "";
  std::printf("%-22s %6.2f %s%s %6.0f%%  %s\n", manoeuvre.name.c_str(), run.score.overall, channels.c_str(),
              on_rig.c_str(), 100.0 * run.peak_stroke_used, run.path.ok() ? "ok" : run.path.Describe().c_str());
}

}  // namespace

PerceptionScore ScoreOnTheRig(const PlatformConfig& nominal, const RigEffects& effects, const CueingConfig& config,
                              const CueingRun& run) {
  const std::vector<Pose> truth = PlayPosesThroughTheStack(nominal, effects, run.commanded, 1.0 / config.rate_hz);
  const VehicleSeries felt = PlatformMotionAtHead(truth, 1.0 / config.rate_hz, config.head_in_platform_m);
  return ScorePerception(config.perception, run.vehicle, felt);
}

int RunOffline(const OfflineOptions& options) {
  const PlatformConfig nominal = LoadConfigFile(options.config_path);
  const PlatformModel model(nominal);
  const CueingConfig config = LoadCueingConfig(options.cueing_path);
  std::optional<RigEffects> effects;
  if (!options.rig_effects_path.empty()) effects = LoadRigEffects(options.rig_effects_path);
  std::vector<Manoeuvre> manoeuvres;
  for (const std::string& path : options.manoeuvre_paths) manoeuvres.push_back(LoadManoeuvre(path));
  if (!options.csv_dir.empty()) std::filesystem::create_directories(options.csv_dir);
  if (!options.plot_dir.empty()) std::filesystem::create_directories(options.plot_dir);
  nlohmann::json runs = nlohmann::json::array();
  double error_sum = 0.0, real_sum = 0.0;
  int violations = 0;
  const CueingAlgorithm algorithm = options.algorithm.empty() ? config.algorithm : AlgorithmNamed(options.algorithm);
  if (!options.json) {
    std::printf("%s: perceived error in thresholds (overall, then fx fy fz wx wy wz%s), stroke used\n",
                CueingAlgorithmName(algorithm), effects ? ", then overall on the rig" : "");
    if (algorithm == CueingAlgorithm::kModelPredictive) {
      const MpcLegRoom room = DeriveMpcLegRoom(model, model.home_pose(), config.mpc.wanted, config.mpc.leg_margin);
      std::printf(
          "the box, every channel at once: %s\neach channel's largest, the others at rest: %s\n",
          DeriveMpcLimits(model, model.home_pose(), config.mpc.wanted, config.mpc.leg_margin).Describe().c_str(),
          room.Box(room.position.most, room.velocity.most, room.acceleration.most).Describe().c_str());
    }
  }
  for (const Manoeuvre& manoeuvre : manoeuvres) {
    const CueingRun run = RunCueing(model, config, algorithm, manoeuvre);
    std::optional<PerceptionScore> real;
    if (effects) real = ScoreOnTheRig(nominal, *effects, config, run);
    error_sum += run.score.overall;
    if (real) real_sum += real->overall;
    violations += run.path.ok() ? 0 : 1;
    if (!options.csv_dir.empty()) {
      const std::string path = (std::filesystem::path(options.csv_dir) / (manoeuvre.name + ".csv")).string();
      std::ofstream csv(path);
      csv << CueingRunCsv(run);
      if (!csv.flush()) throw std::runtime_error(fmt::format("{}: cannot write", path));
    }
    if (!options.plot_dir.empty()) {
      const std::string png =
          PlotCueingRun(run, config.perception, CueingAlgorithmName(algorithm), options.plot_dir, manoeuvre.name);
      if (!options.json) std::printf("%s\n", png.c_str());
    }
    if (options.json)
      runs.push_back(RunJson(manoeuvre, run, real));
    else
      PrintRow(manoeuvre, run, real);
  }
  const double count = static_cast<double>(manoeuvres.size());
  if (options.json) {
    nlohmann::json out = {{"algorithm", CueingAlgorithmName(algorithm)},
                          {"manoeuvres", runs},
                          {"perception_error", error_sum / count},
                          {"limit_violations", violations}};
    if (effects) out["perception_error_real"] = real_sum / count;
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("mean perception error %.3f thresholds%s; %d of %zu manoeuvres leave a limit\n", error_sum / count,
                effects ? fmt::format(" ({:.3f} on the rig)", real_sum / count).c_str() : "", violations,
                manoeuvres.size());
  }
  return 0;
}

nlohmann::json OmctJson(const std::vector<OmctPoint>& points) {
  nlohmann::json out = nlohmann::json::object();
  for (const OmctPoint& p : points) {
    out[CueChannelName(p.channel)].push_back(
        {{"frequency_rad_s", p.frequency_rad_s}, {"gain", p.gain}, {"phase_deg", p.phase_deg}});
  }
  return out;
}

int RunOmctTable(const std::string& config_path, const std::string& cueing_path, bool json) {
  const PlatformModel model(LoadConfigFile(config_path));
  const CueingConfig config = LoadCueingConfig(cueing_path);
  const std::vector<OmctPoint> points = RunOmct(model, config);
  if (json) {
    nlohmann::json out = {{"omct", OmctJson(points)}};
    out["algorithm"] = "classical_washout";
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("OMCT, classical washout: gain / phase (deg) of what the head feels per unit of vehicle motion\n");
  std::printf("%9s", "rad/s");
  for (int channel = 0; channel < kCueChannels; ++channel) std::printf(" %14s", CueChannelName(channel));
  std::printf("\n");
  for (std::size_t f = 0; f < kOmctFrequencies_rad_s.size(); ++f) {
    std::printf("%9.3f", kOmctFrequencies_rad_s[f]);
    for (int channel = 0; channel < kCueChannels; ++channel) {
      const OmctPoint& p = points[static_cast<std::size_t>(channel) * kOmctFrequencies_rad_s.size() + f];
      std::printf(" %6.3f / %5.0f", p.gain, p.phase_deg);
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace edsp
