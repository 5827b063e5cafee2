// edsp-planner: publishes EDSP_SETPOINT at 1 kHz on an absolute clock. The
// whole trajectory is checked against the workspace before the first
// setpoint; after it ends the final pose is held until SIGINT/SIGTERM.
//   edsp-planner [--motions Lz,Lx,Rz,Ry|calibration] [--csv FILE] [--dwell-s 1] [--stops 5]
//                [--exit-after-hold-s S] [--config FILE] [--group FILE] [--session-id N]
//   edsp-planner --motions calibration --identifiability [--json]
//                how well the motions let edsp-gap identify each effect,
//                beside the paper's four motions; publishes nothing
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "edsp/kinematics/config.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/planner/csv_trajectory.h"
#include "edsp/planner/identifiability.h"
#include "edsp/planner/motion_library.h"
#include "edsp/planner/planner.h"
#include "edsp/transport/bus.h"
#include "edsp/node_status_t.hpp"

namespace edsp {
namespace {

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : text + ",") {
    if (c == ',') {
      if (!part.empty()) parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  return parts;
}

std::unique_ptr<TrajectorySequence> BuildTrajectory(const PlatformModel& model,
                                                    const std::string& motions,
                                                    const std::string& csv,
                                                    const PaperMotionOptions& options) {
  if (csv.empty()) return MotionSequence(model, SplitList(motions), options);
  auto sequence = std::make_unique<TrajectorySequence>();
  {
    auto file = std::make_unique<CsvTrajectory>(CsvTrajectory::Load(csv));
    const Vector6 start = file->Sample(0.0).pose;
    const Vector6 home = model.home_pose().ToVector();
    if ((start - home).cwiseAbs().maxCoeff() > 1e-9) {
      sequence->Append("approach", std::make_unique<QuinticMove>(QuinticMove::WithinLimits(
                                       home, start, options.max_speed_m_s, options.max_speed_rad_s)));
    }
    sequence->Append(csv, std::move(file));
  }
  return sequence;
}

nlohmann::json ToJson(const Identifiability& row) {
  return {{"effects", row.effects}, {"parameters", row.parameters}, {"samples", row.samples},
          {"condition", row.condition}, {"o1", row.o1}, {"o3", row.o3}};
}

// The motions' identifiability beside the paper's four (identifiability.h).
int ReportIdentifiability(const PlatformModel& model, const TrajectorySequence& motions,
                          const PaperMotionOptions& paper, const IdentifiabilityOptions& options, bool json) {
  // A motion set the planner would refuse is not one to judge.
  CheckTrajectory(model, motions);
  const auto reference = MotionSequence(model, PaperMotionNames(), paper);
  const std::vector<Identifiability> ours = AssessIdentifiability(model, motions, options);
  const std::vector<Identifiability> theirs = AssessIdentifiability(model, *reference, options);
  if (json) {
    nlohmann::json out = {{"rate_hz", options.rate_hz}, {"noise_sigma_m", options.noise_sigma_m}};
    out["motions"] = {{"duration_s", motions.duration_s()}, {"effects", nlohmann::json::array()}};
    out["paper"] = {{"duration_s", reference->duration_s()}, {"effects", nlohmann::json::array()}};
    for (const Identifiability& row : ours) out["motions"]["effects"].push_back(ToJson(row));
    for (const Identifiability& row : theirs) out["paper"]["effects"].push_back(ToJson(row));
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("identifiability at %.0f Hz, tracker noise %.1f um per axis; parameters in typical sizes\n",
              options.rate_hz, options.noise_sigma_m * 1e6);
  std::printf("these motions %.1f s, the paper's four (Lz Lx Rz Ry) %.1f s\n\n", motions.duration_s(),
              reference->duration_s());
  std::printf("%-20s %4s | %10s %9s %9s | %10s %9s %9s\n", "effects", "par", "condition", "O1", "O3",
              "paper cond", "O1", "O3");
  for (std::size_t k = 0; k < ours.size(); ++k) {
    const Identifiability& a = ours[k];
    const Identifiability& b = theirs[k];
    std::printf("%-20s %4d | %10.3g %9.3g %9.3g | %10.3g %9.3g %9.3g\n", a.effects.c_str(), a.parameters,
                a.condition, a.o1, a.o3, b.condition, b.o1, b.o3);
  }
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-planner: trajectories → EDSP_SETPOINT at 1 kHz"};
  NodeOptions node;
  AddNodeOptions(&app, &node);
  std::string motions = "Lz,Lx,Rz,Ry", csv;
  PaperMotionOptions paper;
  app.add_option("--motions", motions,
                 "motions to run in order (Lx Ly Lz Rx Ry Rz, M1…M999 mixed, calibration)");
  app.add_option("--csv", csv, "play a trajectory CSV instead (time_s,x_m,...,yaw_rad)");
  app.add_option("--stops", paper.stops, "stops across each motion's range")->check(CLI::Range(2, 1000));
  app.add_option("--dwell-s", paper.dwell_s, "dwell at each stop")->check(CLI::Range(0.0, 3600.0));
  app.add_option("--max-speed-m-s", paper.max_speed_m_s)->check(CLI::Range(1e-4, 2.0));
  app.add_option("--max-speed-rad-s", paper.max_speed_rad_s)->check(CLI::Range(1e-4, 4.0));
  double exit_after_hold_s = -1.0;
  app.add_option("--exit-after-hold-s", exit_after_hold_s,
                 "exit after holding the final pose this long (default: hold until stopped)");
  bool identifiability = false, json = false;
  IdentifiabilityOptions assess;
  CLI::Option* assess_flag = app.add_flag(
      "--identifiability", identifiability,
      "print how well the motions identify each effect beside the paper's four, and exit");
  app.add_flag("--json", json, "with --identifiability: JSON on stdout")->needs(assess_flag);
  app.add_option("--tracker-rate-hz", assess.rate_hz, "with --identifiability")
      ->check(CLI::Range(1.0, 10000.0))
      ->needs(assess_flag);
  app.add_option("--tracker-noise-m", assess.noise_sigma_m, "with --identifiability: per axis")
      ->check(CLI::Range(1e-9, 1e-2))
      ->needs(assess_flag);
  CLI11_PARSE(app, argc, argv);

  const PlatformModel model(LoadConfigFile(node.config_path));
  if (identifiability) {
    return ReportIdentifiability(model, *BuildTrajectory(model, motions, csv, paper), paper, assess, json);
  }
  Planner planner(model, BuildTrajectory(model, motions, csv, paper), node.session_id);
  InstallStopSignals();
  Bus bus(TransportFor(node));
  auto setpoints = bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
  auto status_out = bus.Advertise<node_status_t>("EDSP_STATUS");
  NodeStatus status("planner");
  status.SetState(node_status_t::STATE_RUNNING);
  // On the host's millisecond grid: the bridge ticks a fixed phase after it.
  RateClock clock(std::chrono::milliseconds(1), std::chrono::microseconds(0));
  const std::int64_t planner_start = UtimeNow();
  planner.Start(planner_start);
  std::fprintf(stderr, "edsp-planner: %.1f s of motion, session %lld\n",
               planner.sequence().duration_s(), static_cast<long long>(node.session_id));
  while (!StopRequested()) {
    clock.WaitNext();
    const auto start = std::chrono::steady_clock::now();
    const std::int64_t now = UtimeNow();
    if (setpoints.Publish(planner.Step(now))) status.CountOut();
    if (planner.Finished(now)) {
      status.SetState(node_status_t::STATE_HOLDING);
      if (exit_after_hold_s >= 0.0 &&
          static_cast<double>(now - planner_start) * 1e-6 >=
              planner.sequence().duration_s() + exit_after_hold_s) {
        break;
      }
    }
    status.RecordLoop(std::chrono::steady_clock::now() - start);
    if (status.Due(now)) status_out.Publish(status.Report(now, clock.missed()));
  }
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-planner", edsp::Run, argc, argv); }
