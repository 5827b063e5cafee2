// edsp-kinematics: EDSP_SETPOINT → EDSP_LEG_COMMAND (PR compensation in the
// chosen mode), EDSP_LEG_STATE → EDSP_PLATFORM_STATE (100 Hz), EDSP_CONFIG
// latched at 1 Hz. A setpoint it cannot validate becomes an EDSP_FAULT and is
// never forwarded.
//   edsp-kinematics [--pr-mode signed|unsigned|none|asin] [--config FILE]
//                   [--group FILE] [--session-id N] [--stale-ms 50] [--replay]
//                   [--calibration MODEL [--apply-ambiguous]]
// --calibration (or [calibration] model in the config): an edsp-gap model
// (diagnose --save-model) applied to every command and to the forward
// kinematics; the node says which on EDSP_FAULT (info) and on stderr at start.
// --replay: the setpoints come from a log (lcm-logplayer), so they are judged
// by their own clock, not the wall clock, and reproduce the recorded commands.
// EDSP_PR_MODE (pr_mode_t, e.g. from `edsp-ctl pr-mode signed`) switches the
// mode live, blended over 0.5 s; EDSP_CALIBRATION (calibration_t, from
// `edsp-ctl calibration MODEL|off`) switches the calibration live, blended
// over 1 s. Both are answered on EDSP_REPLY: done, or refused with the reason.
// The node on its bus: KinematicsLoop (edsp/kinematics/kinematics_loop.h).
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/kinematics_loop.h"
#include "edsp/kinematics/kinematics_node.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {
namespace {

int Run(int argc, char** argv) {
  NodeApp app{"edsp-kinematics: setpoints → leg commands with PR compensation"};
  std::string mode_text = "signed";
  int stale_ms = 50;
  app.add_option("--pr-mode", mode_text, "none, unsigned (paper Eq. 9), signed, asin (LinuxCNC)");
  app.add_option("--stale-ms", stale_ms, "refuse setpoints older than this")->check(CLI::Range(1, 10000));
  std::string calibration_path;
  bool apply_ambiguous = false;
  app.add_option("--calibration", calibration_path,
                 "edsp-gap model to apply (default: the config's [calibration] model)");
  app.add_flag("--apply-ambiguous", apply_ambiguous, "apply the model's ambiguous effects too");
  bool replay = false;
  app.add_flag("--replay", replay, "judge setpoints by their own clock (input from lcm-logplayer)");
  CLI11_PARSE(app, argc, argv);

  KinematicsNodeOptions options;
  if (!ParsePrMode(mode_text.c_str(), &options.pr_mode)) {
    throw std::runtime_error("--pr-mode " + mode_text + ": use none, unsigned, signed or asin");
  }
  options.session_id = app.node.session_id;
  options.stale_us = std::int64_t{stale_ms} * 1000;
  options.calibration_starts_from_drives = !replay;  // a replay has no drives: its commands are the log's
  const std::string config_text = ReadTextFile(app.node.config_path);
  const PlatformConfig config = LoadConfigFile(app.node.config_path);
  const PlatformModel model(config);
  if (calibration_path.empty()) calibration_path = config.calibration_model;
  if (!calibration_path.empty()) {
    options.calibration =
        calibration::LoadCalibration(calibration_path, model, apply_ambiguous || config.calibration_apply_ambiguous);
  }
  KinematicsNode kinematics(model, options);
  InstallStopSignals();
  Bus bus(TransportFor(app.node));
  KinematicsLoopOptions loop_options;
  loop_options.config_text = config_text;
  loop_options.replay = replay;
  KinematicsLoop loop(bus, kinematics, loop_options);
  loop.Run(StopRequested);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-kinematics", edsp::Run, argc, argv); }
