// edsp-sim: offline kinematics and simulation commands (README "Usage";
// `rig`: docs/rig.md, `stack-table`: docs/stack.md).
//   edsp-sim pr --config FILE --pose x,y,z,roll,pitch,yaw [--json]
//   edsp-sim paper-table --config FILE [--poses N] [--json]
//   edsp-sim stack-table --config FILE LOG... [--plots DIR] [--json]
//       the same table measured by the tracker in logs of the live stack
//   edsp-sim rig --config FILE --out DIR [--motions Lz,Lx,Rz,Ry|calibration] [--pr-mode signed]
//                [--calibration MODEL [--apply-ambiguous]]
//                [--stops 5] [--dwell-s 1] [--tracker-noise-m 0] [--seed 1] [--per-effect] [--json]
//       the virtual rig with the config's [rig.effects] through the motions,
//       offline: DIR/run.lcmlog and DIR/measurement.csv

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/workspace.h"
#include "edsp/sim/paper_table.h"
#include "edsp/kinematics/pose_text.h"
#include "edsp/sim/offline_run.h"
#include "edsp/sim/stack_report.h"

namespace edsp {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

nlohmann::json ToJson(const Vector6& v) { return nlohmann::json::array({v(0), v(1), v(2), v(3), v(4), v(5)}); }

int RunPr(const std::string& config_path, const std::string& pose_text, bool json) {
  const PlatformModel model(LoadConfigFile(config_path));
  const Pose pose = ParsePoseText(pose_text);
  const WorkspaceCheck check = CheckWorkspace(model, pose);
  if (!check.ok()) {
    throw std::runtime_error(fmt::format("pose {} is outside the workspace: {}", DescribePose(pose), check.Describe()));
  }
  const LegSolution legs = model.Solve(pose);
  const Vector6 pr_error = model.PrLengthError(legs, PrMode::kSigned);
  const Vector6 change = legs.twist_rad - model.home_twist_rad();
  if (json) {
    nlohmann::json out;
    out["length_m"] = ToJson(legs.length_m);
    out["twist_rad"] = ToJson(legs.twist_rad);
    out["pr_correction_m"] = ToJson(pr_error);
    out["twist_home_rad"] = ToJson(model.home_twist_rad());
    out["compensated_length_m"] = ToJson(legs.length_m - pr_error);
    for (PrMode mode : {PrMode::kUnsigned, PrMode::kAsin}) {
      out["pr_correction_by_mode_m"][PrModeName(mode)] = ToJson(model.PrLengthError(legs, mode));
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("pose: %s\n", DescribePose(pose).c_str());
  std::printf("leg  length_m      twist_deg  d_twist_deg  pr_correction_mm  command_m\n");
  for (int i = 0; i < kNumLegs; ++i) {
    std::printf("%3d  %.9f  %9.4f  %11.4f  %16.6f  %.9f\n", i + 1, legs.length_m(i), legs.twist_rad(i) * kRadToDeg,
                change(i) * kRadToDeg, pr_error(i) * 1e3, legs.length_m(i) - pr_error(i));
  }
  return 0;
}

// Millimetres with six decimals, or scientific below that (the signed
// column's sub-nanometre residue must not print as a misleading bare 0).
std::string FormatMm(double metres) {
  const double mm = metres * 1e3;
  return mm >= 5e-7 || mm == 0.0 ? fmt::format("{:.6f}", mm) : fmt::format("{:.1e}", mm);
}

void PrintTable(const std::vector<MotionRow>& rows, const PlatformModel& model) {
  const DriveParameters& drive = model.config().drive;
  std::printf(
      "Maximum error at observation point A over the paper's test motions (mm)\n"
      "commands built with each PR model; the platform moves with the true signed PR\n"
      "lead %.4g mm, pr_sign %+d\n\n",
      drive.lead_m * 1e3, drive.pr_sign);
  std::printf("%-7s %-14s %12s %16s %14s %16s\n", "motion", "range", "no PR comp.", "unsigned Eq.(9)", "signed (edsp)",
              "asin (LinuxCNC)");
  for (const MotionRow& row : rows) {
    const bool linear = row.motion.axis < 3;
    const std::string range = linear ? fmt::format("±{:g} m", row.motion.amplitude)
                                     : fmt::format("±{:g} deg", row.motion.amplitude * kRadToDeg);
    std::printf("%-7s %-14s %12s %16s %14s %16s\n", row.motion.name.c_str(), range.c_str(),
                FormatMm(row.max_error_m[0]).c_str(), FormatMm(row.max_error_m[1]).c_str(),
                FormatMm(row.max_error_m[2]).c_str(), FormatMm(row.max_error_m[3]).c_str());
  }
  std::printf(
      "\nPaper Table 1, simulation (mm): conventional 0.03006 0.02431 0.04637 0.05836;\n"
      "with its Eq.(9) compensation 0.002486 0.003283 0.01097 0.02955 (Lz Lx Rz Ry).\n");
}

int RunPaperTable(const std::string& config_path, int poses, bool json) {
  if (poses < 2 || poses > 100000) {
    throw std::runtime_error(fmt::format("--poses {} must be in 2..100000", poses));
  }
  const PlatformModel model(LoadConfigFile(config_path));
  const std::vector<MotionRow> rows = PaperTable(model, poses);
  if (!json) {
    PrintTable(rows, model);
    return 0;
  }
  nlohmann::json out;
  for (const MotionRow& row : rows) {
    nlohmann::json& m = out["motions"][row.motion.name];
    for (std::size_t k = 0; k < kTableModes.size(); ++k) {
      m[fmt::format("{}_max_m", PrModeName(kTableModes[k]))] = row.max_error_m[k];
    }
    m["poses"] = poses;
  }
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

int RunStackTable(const std::string& config_path, const std::vector<std::string>& logs, const std::string& plots_dir,
                  bool json) {
  const PlatformModel model(LoadConfigFile(config_path));
  std::vector<DwellError> dwells;
  int status = 0;
  for (const std::string& log : logs) {
    const DwellErrors run = DwellErrorsFromLog(log, model);
    if (run.dwells.empty()) throw std::runtime_error(log + ": no completed dwell with tracker data");
    if (run.damaged) {
      std::fprintf(stderr, "edsp-sim: %s is damaged at byte %lld; using the dwells before it\n", log.c_str(),
                   static_cast<long long>(run.damage_offset));
      status = 3;
    }
    dwells.insert(dwells.end(), run.dwells.begin(), run.dwells.end());
  }
  const std::vector<StackTableRow> rows = StackTable(dwells, model);
  std::vector<std::string> pngs;
  if (!plots_dir.empty()) pngs = WriteStackPlots(dwells, model, plots_dir);
  if (json) {
    nlohmann::json out;
    out["rows"] = nlohmann::json::array();
    for (const StackTableRow& r : rows) {
      out["rows"].push_back({{"motion", r.motion},
                             {"pr_mode", PrModeName(r.mode)},
                             {"stops", r.stops},
                             {"max_measured_m", r.max_measured_m},
                             {"rms_measured_m", r.rms_measured_m},
                             {"max_predicted_m", r.max_predicted_m}});
    }
    out["plots"] = pngs;
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("Point-A error at the dwells, max over the stops: tracker (model prediction), mm\n%s",
                FormatStackTable(rows).c_str());
    for (const std::string& png : pngs) std::printf("plot: %s\n", png.c_str());
  }
  return status;
}

int RunPerEffect(const std::string& config_path, const OfflineRunOptions& options, bool json) {
  const std::vector<EffectError> table = PerEffectErrors(config_path, options);
  if (json) {
    nlohmann::json out = nlohmann::json::object();
    for (const EffectError& e : table) out[e.effect] = {{"max_m", e.max_error_m}, {"rms_m", e.rms_error_m}};
    std::printf("%s\n", nlohmann::json{{"effects", out}}.dump(2).c_str());
  } else {
    std::printf("%-22s %12s %12s\n", "effect (alone)", "max_um", "rms_um");
    for (const EffectError& e : table) {
      std::printf("%-22s %12.1f %12.1f\n", e.effect.c_str(), e.max_error_m * 1e6, e.rms_error_m * 1e6);
    }
  }
  return 0;
}

int RunRig(const std::string& config_path, OfflineRunOptions options, const std::string& mode_text,
           const std::string& frame_text, bool per_effect, bool json) {
  if (!ParsePrMode(mode_text.c_str(), &options.pr_mode)) {
    throw std::runtime_error("--pr-mode " + mode_text + ": use none, unsigned, signed or asin");
  }
  if (!frame_text.empty()) options.tracker.X_TB = ParsePoseText(frame_text);
  if (per_effect) return RunPerEffect(config_path, options, json);
  const auto start = std::chrono::steady_clock::now();
  const OfflineRunResult r = RunOffline(config_path, options);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (json) {
    const nlohmann::json out = {{"log", r.log_path},
                                {"measurement_csv", r.csv_path},
                                {"cycles", r.cycles},
                                {"tracker_samples", r.tracker_samples},
                                {"faults", r.faults},
                                {"simulated_s", r.duration_s},
                                {"max_error_m", r.max_error_m},
                                {"rms_error_m", r.rms_error_m},
                                {"wall_s", wall_s},
                                {"faster_than_real_time", r.duration_s / wall_s},
                                {"calibration", r.calibration}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf(
        "%.1f s simulated in %.1f s (%.0fx real time): %lld tracker samples, %lld faults\n"
        "point-A error: max %.1f um, rms %.1f um\n%s\n%s\n",
        r.duration_s, wall_s, r.duration_s / wall_s, static_cast<long long>(r.tracker_samples),
        static_cast<long long>(r.faults), r.max_error_m * 1e6, r.rms_error_m * 1e6, r.log_path.c_str(),
        r.csv_path.c_str());
    if (!r.calibration.empty()) std::printf("calibration: %s\n", r.calibration.c_str());
  }
  return r.faults == 0 ? 0 : 2;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-sim: offline kinematics, passive rotation and accuracy tables"};
  app.require_subcommand(1);
  std::string config_path;
  std::string pose_text;
  bool json = false;
  int poses = 41;

  CLI::App* pr = app.add_subcommand("pr", "leg lengths, signed twists and PR corrections at a pose");
  pr->add_option("--config", config_path, "platform config (TOML)")->required();
  pr->add_option("--pose", pose_text, "x,y,z,roll,pitch,yaw in m and rad (use --pose=-0.1,...)")->required();
  pr->add_flag("--json", json, "print JSON");

  CLI::App* table =
      app.add_subcommand("paper-table", "point-A error of the paper's four test motions per PR compensation mode");
  table->add_option("--config", config_path, "platform config (TOML)")->required();
  table->add_option("--poses", poses, "poses per motion (the paper's figures: 41)");
  table->add_flag("--json", json, "print JSON");

  CLI::App* stack = app.add_subcommand(
      "stack-table", "the table measured by the tracker in logs of the live stack (Table 1, Figs. 6-9)");
  std::vector<std::string> logs;
  std::string plots_dir;
  stack->add_option("--config", config_path, "platform config (TOML)")->required();
  stack->add_option("logs", logs, "LCM logs of sim-group runs (any PR modes)")->required();
  stack->add_option("--plots", plots_dir, "write error-against-displacement PNGs here");
  stack->add_flag("--json", json, "print JSON");

  CLI::App* rig = app.add_subcommand("rig", "the virtual rig with its [rig.effects] through test motions, offline");
  edsp::OfflineRunOptions offline;
  std::string mode_text = "signed", frame_text;
  rig->add_option("--config", config_path, "platform config (TOML) with [rig.effects]")->required();
  rig->add_option("--out", offline.out_dir, "directory for run.lcmlog and measurement.csv")->required();
  rig->add_option("--motions", offline.motions, "motions in order (Lx Ly Lz Rx Ry Rz, M1…M999 mixed, calibration)")
      ->delimiter(',');
  rig->add_option("--pr-mode", mode_text, "compensation the kinematics node runs");
  rig->add_option("--stops", offline.paper.stops)->check(CLI::Range(2, 1000));
  rig->add_option("--dwell-s", offline.paper.dwell_s)->check(CLI::Range(0.0, 3600.0));
  rig->add_option("--max-speed-m-s", offline.paper.max_speed_m_s)->check(CLI::Range(1e-4, 2.0));
  rig->add_option("--max-speed-rad-s", offline.paper.max_speed_rad_s)->check(CLI::Range(1e-4, 4.0));
  rig->add_option("--tracker-noise-m", offline.tracker.noise_sigma_m, "1-sigma per axis")->check(CLI::Range(0.0, 0.01));
  rig->add_option("--tracker-rate-hz", offline.tracker.rate_hz)->check(CLI::Range(1.0, 1000.0));
  rig->add_option("--tracker-frame", frame_text, "pose of {B} in the tracker frame, x,y,z,roll,pitch,yaw");
  rig->add_option("--seed", offline.tracker.seed, "tracker noise seed");
  rig->add_option("--calibration", offline.calibration_path,
                  "edsp-gap model (diagnose --save-model) the kinematics applies; default: the config's "
                  "[calibration] model");
  rig->add_flag("--apply-ambiguous", offline.apply_ambiguous, "apply the model's ambiguous effects too");
  bool per_effect = false;
  rig->add_flag("--per-effect", per_effect, "one run per enabled effect alone: its point-A error");
  rig->add_flag("--json", json, "print JSON");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*pr) return edsp::RunPr(config_path, pose_text, json);
    if (*rig) return edsp::RunRig(config_path, offline, mode_text, frame_text, per_effect, json);
    if (*stack) return edsp::RunStackTable(config_path, logs, plots_dir, json);
    return edsp::RunPaperTable(config_path, poses, json);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-sim: error: %s\n", e.what());
    return 1;
  }
}
