// edsp-planner: publishes EDSP_SETPOINT at 1 kHz on an absolute clock and
// serves motion requests (EDSP_MOTION_REQUEST, from edsp-ctl). Started with
// a program (--motions or --csv) it plays it at once, checked whole before
// the first setpoint, then holds its final pose; without one it holds home.
// Either way it serves requests until SIGINT/SIGTERM.
//   edsp-planner [--motions Lz,Lx,Rz,Ry|calibration] [--csv FILE] [--dwell-s 1] [--stops 5]
//                [--exit-after-hold-s S] [--config FILE] [--group FILE] [--session-id N]
//   edsp-planner --motions calibration --identifiability [--json]
//                how well the motions let edsp-gap identify each effect,
//                beside the paper's four motions; publishes nothing
#include <cstdio>

#include "edsp/kinematics/config.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/planner/identifiability_report.h"
#include "edsp/planner/motion_library.h"
#include "edsp/planner/planner_loop.h"
#include "edsp/transport/bus.h"

namespace edsp {
namespace {

int Run(int argc, char** argv) {
  NodeApp app{"edsp-planner: trajectories → EDSP_SETPOINT at 1 kHz"};
  std::string motions, csv;
  PaperMotionOptions paper;
  app.add_option("--motions", motions,
                 "motions to run at once, in order (Lx Ly Lz Rx Ry Rz, M1…M999 mixed, calibration); "
                 "without them or --csv the planner holds home and serves requests");
  app.add_option("--csv", csv, "play a trajectory CSV instead (time_s,x_m,...,yaw_rad)");
  app.add_option("--stops", paper.stops, "stops across each motion's range")->check(CLI::Range(2, 1000));
  app.add_option("--dwell-s", paper.dwell_s, "dwell at each stop")->check(CLI::Range(0.0, 3600.0));
  app.add_option("--max-speed-m-s", paper.max_speed_m_s)->check(CLI::Range(1e-4, 2.0));
  app.add_option("--max-speed-rad-s", paper.max_speed_rad_s)->check(CLI::Range(1e-4, 4.0));
  PlannerLoopOptions loop;
  app.add_option("--exit-after-hold-s", loop.exit_after_hold_s,
                 "exit after holding the final pose this long (default: hold until stopped)");
  int cue_stale_ms = 20;
  app.add_option("--cue-stale-ms", cue_stale_ms,
                 "while cueing: end it and hold when no valid EDSP_CUE_SETPOINT came for this long")
      ->check(CLI::Range(1, 10000));
  bool identifiability = false, json = false;
  IdentifiabilityOptions assess;
  CLI::Option* assess_flag =
      app.add_flag("--identifiability", identifiability,
                   "print how well the motions identify each effect beside the paper's four, and exit");
  app.add_flag("--json", json, "with --identifiability: JSON on stdout")->needs(assess_flag);
  app.add_option("--tracker-rate-hz", assess.rate_hz, "with --identifiability")
      ->check(CLI::Range(1.0, 10000.0))
      ->needs(assess_flag);
  app.add_option("--tracker-noise-m", assess.noise_sigma_m, "with --identifiability: per axis")
      ->check(CLI::Range(1e-9, 1e-2))
      ->needs(assess_flag);
  CLI11_PARSE(app, argc, argv);

  const PlatformModel model(LoadConfigFile(app.node.config_path));
  const bool program = !motions.empty() || !csv.empty();
  if (identifiability) {
    if (!program) throw std::invalid_argument("--identifiability: give --motions or --csv");
    ReportIdentifiability(model, *PlannedTrajectory(model, motions, csv, paper), paper, assess, json);
    return 0;
  }
  MotionServiceOptions serve;
  serve.session_id = app.node.session_id;
  serve.cue_stale_s = cue_stale_ms * 1e-3;
  serve.programs = [&model, paper](const std::string& list) { return MotionSequence(model, MotionNames(list), paper); };
  MotionService service(model, serve);
  if (program) {
    auto trajectory = PlannedTrajectory(model, motions, csv, paper);
    const double duration_s = trajectory->duration_s();
    service.StartProgram(std::move(trajectory), csv.empty() ? motions : csv);
    std::fprintf(stderr, "edsp-planner: %.1f s of motion, session %lld\n", duration_s,
                 static_cast<long long>(app.node.session_id));
  } else {
    std::fprintf(stderr, "edsp-planner: holding home, serving motion requests, session %lld\n",
                 static_cast<long long>(app.node.session_id));
  }
  InstallStopSignals();
  Bus bus(TransportFor(app.node));
  PlannerLoop planner_loop(bus, service, loop);
  RateClock clock(kPlannerPeriod, std::chrono::microseconds(0));
  planner_loop.Run(clock, StopRequested);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-planner", edsp::Run, argc, argv); }
