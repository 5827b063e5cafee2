// edsp-cueing: motion cueing (docs/cueing.md).
//   edsp-cueing offline --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                       [--csv-dir DIR] [--plot DIR] [--algorithm classical_washout|mpc] [--json]
//       each manoeuvre through a cueing algorithm at the cueing rate: every
//       setpoint through the kinematics' whole-path check, and what a rider
//       on the commanded platform perceives against the vehicle; with
//       --rig-effects, also on the platform's real motion (the setpoints
//       played through the stack and a rig with that file's [rig.effects]).
//   edsp-cueing omct --config FILE --cueing FILE [--json]
//       the Objective Motion Cueing Test's direct responses: gain and phase
//       per channel at the test's twelve frequencies.
//   edsp-cueing bench --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                     [--cycles 1000000] [--seed 1] [--variants 3] [--variant-seed 2026] [--json]
//       deploy/edsp bench cueing: per algorithm the manoeuvres' perception
//       errors (commanded and real, and over variants of them no setting was
//       chosen on), a soak of random vehicle motion counting refused
//       setpoints and the solve's time; their ratios; the OMCT.
//   edsp-cueing live --cueing FILE [--input udp|lcm] [--udp ADDRESS:PORT] [--config FILE] [--group FILE]
//                    [--session-id N]
//       the cueing source in a running group (live_command.h).
//   edsp-cueing send --manoeuvre FILE [--to ADDRESS:PORT|lcm] [--rate-hz 250] [--lead-s 5]
//                    [--after disengage|silence|estop|freeze|engage] [--tail-s 20] [--sent-log FILE]
//                    [--group FILE | --lcm-url URL] [--session-id N|auto]
//       a vehicle model's stand-in: the manoeuvre as packets, in real time (send_command.h).
//   edsp-cueing delay --log RUN.lcmlog --sent SENT.csv [--json]
//       each sample's delay from its sender to the drives, traced through the log (delay_command.h).
//   edsp-cueing score --log RUN.lcmlog --cueing FILE [--json]
//       a live run's cueing scored from its log, on the commanded and the real motion (score_command.h).

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/cueing/cueing_plot.h"
#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/manoeuvre_variants.h"
#include "edsp/cueing/cueing_soak.h"
#include "edsp/cueing/omct.h"
#include "edsp/cueing/platform_motion.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/sim/played_poses.h"
#include "delay_command.h"
#include "live_command.h"
#include "perception_json.h"
#include "score_command.h"
#include "send_command.h"

namespace edsp {
namespace {

struct OfflineOptions {
  std::string config_path;
  std::string cueing_path;
  std::vector<std::string> manoeuvre_paths;
  std::string rig_effects_path;
  std::string csv_dir;
  std::string plot_dir;
  std::string algorithm;  // empty: the cueing config's [cueing] algorithm
  bool json = false;
};

CueingAlgorithm AlgorithmNamed(const std::string& name) {
  const std::optional<CueingAlgorithm> algorithm = CueingAlgorithmFromName(name);
  if (!algorithm) {
    throw std::invalid_argument(fmt::format("--algorithm {}: not one of classical_washout, mpc", name));
  }
  return *algorithm;
}

// What a rider on the rig feels: the commanded poses played through the
// stack and a rig with its effects.
PerceptionScore ScoreOnTheRig(const PlatformConfig& nominal, const RigEffects& effects, const CueingConfig& config,
                              const CueingRun& run) {
  const std::vector<Pose> truth = PlayPosesThroughTheStack(nominal, effects, run.commanded, 1.0 / config.rate_hz);
  const VehicleSeries felt = PlatformMotionAtHead(truth, 1.0 / config.rate_hz, config.head_in_platform_m);
  return ScorePerception(config.perception, run.vehicle, felt);
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

struct BenchOptions {
  OfflineOptions offline;
  std::int64_t cycles = 1'000'000;
  std::uint64_t seed = 1;
  int variants = 3;  // per manoeuvre, none tuned on
  std::uint64_t variant_seed = 2026;
};

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
  offline_command
      ->add_option("--rig-effects", offline.rig_effects_path,
                   "score on the real motion too: a config whose [rig.effects] the rig has")
      ->check(CLI::ExistingFile);
  offline_command->add_option("--csv-dir", offline.csv_dir, "write <manoeuvre>.csv per manoeuvre here");
  offline_command->add_option("--plot", offline.plot_dir,
                              "draw <manoeuvre>.png per manoeuvre here: perceived, vehicle against platform");
  offline_command->add_option("--algorithm", offline.algorithm,
                              "classical_washout or mpc (default: the cueing config's [cueing] algorithm)");
  offline_command->add_flag("--json", offline.json, "JSON on stdout");
  std::string omct_config, omct_cueing;
  bool omct_json = false;
  CLI::App* omct_command = app.add_subcommand("omct", "the OMCT's direct responses of classical washout");
  omct_command->add_option("--config", omct_config, "platform config (TOML)")->required()->check(CLI::ExistingFile);
  omct_command->add_option("--cueing", omct_cueing, "cueing config (TOML)")->required()->check(CLI::ExistingFile);
  omct_command->add_flag("--json", omct_json, "JSON on stdout");
  edsp::BenchOptions bench;
  CLI::App* bench_command = app.add_subcommand("bench", "the cueing's figures (deploy/edsp bench cueing)");
  bench_command->add_option("--config", bench.offline.config_path, "platform config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--cueing", bench.offline.cueing_path, "cueing config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--manoeuvre", bench.offline.manoeuvre_paths, "manoeuvre file(s) (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--rig-effects", bench.offline.rig_effects_path, "score on the real motion too")
      ->check(CLI::ExistingFile);
  bench_command->add_option("--cycles", bench.cycles, "cycles of random vehicle motion")
      ->check(CLI::Range(1, 10'000'000));
  bench_command->add_option("--seed", bench.seed, "the random vehicle's seed");
  bench_command->add_option("--variants", bench.variants, "variants of each manoeuvre scored too (0: none)")
      ->check(CLI::Range(0, 100));
  bench_command->add_option("--variant-seed", bench.variant_seed, "the variants' seed");
  bench_command->add_flag("--json", bench.offline.json, "JSON on stdout");
  edsp::LiveOptions live;
  CLI::App* live_command = app.add_subcommand("live", "the cueing source in a running group (EDSP_CUE_SETPOINT)");
  edsp::AddNodeOptions(live_command, &live.node);
  live_command->add_option("--cueing", live.cueing_path, "cueing config (TOML)")->required()->check(CLI::ExistingFile);
  live_command->add_option("--input", live.input, "the vehicle's samples: udp (--udp) or lcm (EDSP_VEHICLE)")
      ->capture_default_str()
      ->check(CLI::IsMember({"udp", "lcm"}));
  live_command->add_option("--udp", live.udp, "the vehicle's packets: ADDRESS:PORT (\"\": none)")
      ->capture_default_str();
  edsp::SendOptions send;
  CLI::App* send_command = app.add_subcommand("send", "a manoeuvre as the vehicle's packets, in real time");
  send_command->add_option("--manoeuvre", send.manoeuvre_path, "manoeuvre file (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  send_command->add_option("--to", send.to, "ADDRESS:PORT, or lcm: EDSP_VEHICLE on the group's bus")
      ->capture_default_str();
  send_command->add_option("--group", send.group_path, "with --to lcm: the bus of this group file")
      ->check(CLI::ExistingFile);
  send_command->add_option("--lcm-url", send.lcm_url, "with --to lcm: this LCM URL");
  send_command->add_option("--session-id", send.session, "with --to lcm: the session, or auto (from its traffic)")
      ->capture_default_str();
  send_command->add_option("--rate-hz", send.rate_hz, "packets per second")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 2000.0));
  send_command->add_option("--lead-s", send.lead_s, "at rest with engage first")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 600.0));
  send_command->add_option("--after", send.after, "then: disengage, silence, estop, freeze or engage")
      ->capture_default_str();
  send_command->add_option("--tail-s", send.tail_s, "for this long")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 600.0));
  send_command->add_option("--sent-log", send.sent_log_path, "CSV of each packet's sequence and send time");
  edsp::ScoreOptions score;
  CLI::App* score_command =
      app.add_subcommand("score", "a live run's cueing scored from its log: commanded and real motion");
  score_command->add_option("--log", score.log_path, "the group's log (.lcmlog)")->required()->check(CLI::ExistingFile);
  score_command->add_option("--cueing", score.cueing_path, "cueing config (TOML): the head, the vestibular models")
      ->required()
      ->check(CLI::ExistingFile);
  score_command->add_flag("--json", score.json, "JSON on stdout");
  edsp::DelayOptions delay;
  CLI::App* delay_command =
      app.add_subcommand("delay", "each vehicle sample's delay from its sender to the drives, from a group's log");
  delay_command->add_option("--log", delay.log_path, "the group's log (.lcmlog)")->required()->check(CLI::ExistingFile);
  delay_command->add_option("--sent", delay.sent_path, "edsp-cueing send --sent-log's CSV")
      ->required()
      ->check(CLI::ExistingFile);
  delay_command->add_flag("--json", delay.json, "JSON on stdout");
  CLI11_PARSE(app, argc, argv);
  try {
    if (live_command->parsed()) return edsp::RunLive(live);
    if (send_command->parsed()) return edsp::RunSend(send);
    if (delay_command->parsed()) return edsp::RunDelay(delay);
    if (score_command->parsed()) return edsp::RunScore(score);
    if (omct_command->parsed()) return edsp::RunOmctTable(omct_config, omct_cueing, omct_json);
    if (bench_command->parsed()) return edsp::RunBench(bench);
    return edsp::RunOffline(offline);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-cueing: %s\n", e.what());
    return 1;
  }
}
