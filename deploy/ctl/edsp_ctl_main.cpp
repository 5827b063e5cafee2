// edsp-ctl: an operator's commands to a running group, over LCM.
//   edsp-ctl [common options] COMMAND [options]
//   edsp-ctl move|check|jog|run|halt|stop|wait|status|frame|pivot|limits ...
//       the planner's motion service (motion_commands.h, docs/operating.md)
//   edsp-ctl arm [--operator NAME] [--session-id N|auto] [--group FILE | --lcm-url URL]
//       re-arm the actuator bridge after it latched a hold (EDSP_ARM)
//   edsp-ctl pr-mode none|unsigned|signed|asin [same options]
//       switch the kinematics node's PR compensation live (EDSP_PR_MODE)
//   edsp-ctl calibration MODEL|off [--apply-ambiguous] [same options]
//       switch the kinematics node's calibration live (EDSP_CALIBRATION): the
//       edsp-gap-model/1 file MODEL (sent whole), or none; blended over 1 s
// The common options (session, operator, group, LCM URL, answer timeout)
// go before the command or after it. --session-id auto (the default)
// listens for up to the answer timeout (2 s) for the group's leg commands
// or setpoints and takes their session; several sessions on the bus (two
// groups) is an error naming them. The command then waits as long for the
// node's reply on EDSP_REPLY (node/request_client.h: sent again every
// 0.5 s until answered) and prints it (a refusal on stderr, with its
// code's name); the exit code comes from the reply's code: 0 done, 2
// refused or unanswered, 1 failed.
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
#include "edsp/kinematics/passive_rotation.h"
#include "edsp/planner/motion_client.h"
#include "edsp/reply_codes.h"
#include "edsp/reply_t.hpp"
#include "edsp/pr_mode_t.hpp"
#include "ctl_session.h"
#include "motion_commands.h"

namespace edsp {
namespace {

using ctl::CtlOptions;

// Sends the operator's request to its node and prints the reply; the exit
// code from the reply's code.
template <typename Msg>
int SendAndConfirm(const CtlOptions& o, const std::string& channel, const Msg& request) {
  MotionClient link(ctl::Transport(o), ctl::GivenSession(o), o.timeout_s, ctl::OperatorName(o));
  const std::optional<reply_t> reply = link.SendOperator(channel, request);
  if (!reply) {
    std::fprintf(stderr, "edsp-ctl: no reply to %s within %g s\n", channel.c_str(), o.timeout_s);
    return ctl::kRefused;
  }
  if (FamilyOf(reply->code) != ReplyFamily::kDone) {
    std::fprintf(stderr, "edsp-ctl: %s refused (%s): %s\n", reply->node.c_str(),
                 std::string(ReplyCodeName(reply->code)).c_str(), reply->reason.c_str());
    return ctl::ExitFor(reply->code);
  }
  std::printf("%s: %s\n", reply->node.c_str(), reply->reason.c_str());
  return ctl::kDone;
}

int Arm(const CtlOptions& o) { return SendAndConfirm(o, channel::kArm, arm_t{}); }

int SetPrMode(const CtlOptions& o, const std::string& mode_text) {
  PrMode mode;
  if (!ParsePrMode(mode_text.c_str(), &mode)) {
    throw std::runtime_error("pr-mode " + mode_text + ": use none, unsigned, signed or asin");
  }
  pr_mode_t request{};
  request.pr_mode = static_cast<std::int8_t>(mode);
  return SendAndConfirm(o, channel::kPrMode, request);
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
  return SendAndConfirm(o, channel::kCalibration, request);
}

// The operator commands' own: --timeout-s is their answer timeout.
void AddCommon(CLI::App* cmd, CtlOptions* o) {
  ctl::AddCommonOptions(cmd, o);
  cmd->add_option("--timeout-s", o->timeout_s, "how long to wait for the group's traffic and for the reply")
      ->check(CLI::Range(0.1, 600.0));
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-ctl: operator commands to a running edsp group"};
  app.require_subcommand(1);
  edsp::CtlOptions options;
  edsp::ctl::AddCommonOptions(&app, &options);
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
