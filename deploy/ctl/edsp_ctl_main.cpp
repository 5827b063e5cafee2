// edsp-ctl: an operator's commands to a running group, over LCM.
//   edsp-ctl move|check|run|halt|stop|wait|status|frame|pivot|limits ...
//       the planner's motion service (motion_commands.h, docs/operating.md)
//   edsp-ctl arm [--operator NAME] [--session-id N|auto] [--group FILE | --lcm-url URL]
//       re-arm the actuator bridge after it latched a hold (EDSP_ARM)
//   edsp-ctl pr-mode none|unsigned|signed|asin [same options]
//       switch the kinematics node's PR compensation live (EDSP_PR_MODE)
//   edsp-ctl calibration MODEL|off [--apply-ambiguous] [same options]
//       switch the kinematics node's calibration live (EDSP_CALIBRATION): the
//       edsp-gap-model/1 file MODEL (sent whole), or none; blended over 1 s
// --session-id auto (the default) listens for up to --timeout-s (2 s) for
// the group's leg commands or setpoints and takes their session; several
// sessions on the bus (two groups) is an error naming them. The command then
// waits up to --timeout-s for the node's confirmation on EDSP_FAULT and
// prints it; exit 0 only if confirmed, 2 if refused or unanswered. Request
// and answer are single UDP datagrams among the group's kHz traffic, so the
// same request goes out again every 0.5 s until answered: the node acts on
// it once and answers every copy alike (node/operator_requests.h).
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "edsp/arm_t.hpp"
#include "edsp/calibration_t.hpp"
#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/kinematics/passive_rotation.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/operator_client.h"
#include "edsp/node/runtime.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/pr_mode_t.hpp"
#include "edsp/transport/bus.h"
#include "ctl_session.h"
#include "motion_commands.h"

namespace edsp {
namespace {

using ctl::CtlOptions;
using ctl::SessionId;
using ctl::Transport;

// Fills the request's session and operator, sends it until `node` answers
// (operator_client.h), and prints the answer: 0 if it acted, 2 if it
// refused or did not answer.
template <typename Msg>
int SendAndConfirm(const CtlOptions& o, const std::string& channel, Msg request, const std::string& node) {
  Bus bus(Transport(o));
  request.session_id = SessionId(bus, o);
  request.operator_name = ctl::OperatorName(o);
  const OperatorAnswer answer = SendOperatorRequest(bus, channel, request, node, o.timeout_s);
  if (!answer.given) {
    std::fprintf(stderr, "edsp-ctl: no answer from %s within %g s\n", node.c_str(), o.timeout_s);
    return 2;
  }
  std::printf("%s: %s\n", node.c_str(), answer.reason.c_str());
  return answer.confirmed ? 0 : 2;
}

int Arm(const CtlOptions& o) { return SendAndConfirm(o, channel::kArm, arm_t{}, "actuator_bridge"); }

int SetPrMode(const CtlOptions& o, const std::string& mode_text) {
  PrMode mode;
  if (!ParsePrMode(mode_text.c_str(), &mode)) {
    throw std::runtime_error("pr-mode " + mode_text + ": use none, unsigned, signed or asin");
  }
  pr_mode_t request{};
  request.pr_mode = static_cast<std::int8_t>(mode);
  return SendAndConfirm(o, channel::kPrMode, request, "kinematics");
}

// The model file's text, read before anything goes on the bus: a file that
// cannot be read is the operator's error, named here; what it says is the
// kinematics node's to judge (against its platform), and it answers why.
std::string ModelText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("calibration " + path + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().empty()) {
    throw std::runtime_error("calibration " + path + ": the file is empty (to switch the calibration off, give off)");
  }
  return text.str();
}

int SetCalibration(const CtlOptions& o, const std::string& model, bool apply_ambiguous) {
  calibration_t request{};
  request.origin = model;
  request.model_json = model == "off" ? "" : ModelText(model);
  request.apply_ambiguous = apply_ambiguous ? 1 : 0;
  return SendAndConfirm(o, channel::kCalibration, request, "kinematics");
}

void AddCommon(CLI::App* cmd, CtlOptions* o) {
  cmd->add_option("--session-id", o->session, "the group's session, or auto (from its traffic)");
  cmd->add_option("--operator", o->operator_name, "who does it, for the log");
  cmd->add_option("--group", o->group_file, "take the LCM URL from this group file");
  cmd->add_option("--lcm-url", o->lcm_url, "LCM URL (default: the edsp default, host-only)");
  cmd->add_option("--timeout-s", o->timeout_s, "how long to wait for the group's traffic and for the answer")
      ->check(CLI::Range(0.1, 600.0));
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-ctl: operator commands to a running edsp group"};
  app.require_subcommand(1);
  edsp::CtlOptions options;
  std::string mode;
  CLI::App* arm = app.add_subcommand("arm", "re-arm the actuator bridge after a latched hold");
  edsp::AddCommon(arm, &options);
  CLI::App* pr = app.add_subcommand("pr-mode", "switch PR compensation live (blended over 0.5 s)");
  pr->add_option("mode", mode, "none, unsigned, signed or asin")->required();
  edsp::AddCommon(pr, &options);
  std::string model;
  bool apply_ambiguous = false;
  CLI::App* calibration =
      app.add_subcommand("calibration", "switch the kinematics' calibration live (blended over 1 s)");
  calibration->add_option("model", model, "an edsp-gap-model/1 file (edsp-gap diagnose --save-model), or off")
      ->required();
  calibration->add_flag("--apply-ambiguous", apply_ambiguous, "apply the model's ambiguous effects too");
  edsp::AddCommon(calibration, &options);
  edsp::ctl::MotionArgs motion;
  edsp::ctl::AddMotionCommands(&app, &options, &motion);
  CLI11_PARSE(app, argc, argv);
  try {
    if (int code = 0; edsp::ctl::RunMotionCommand(app, options, motion, &code)) return code;
    if (*arm) return edsp::Arm(options);
    if (*calibration) return edsp::SetCalibration(options, model, apply_ambiguous);
    return edsp::SetPrMode(options, mode);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-ctl: error: %s\n", e.what());
    return 1;
  }
}
