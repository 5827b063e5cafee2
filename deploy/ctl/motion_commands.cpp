#include "motion_commands.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/kinematics/pose_text.h"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/planner/motion_client.h"
#include "edsp/planner/motion_request_checks.h"
#include "edsp/reply_codes.h"

namespace edsp::ctl {

namespace {

template <std::size_t N>
nlohmann::json Array(const double (&v)[N]) {
  return nlohmann::json(std::vector<double>(v, v + N));
}

nlohmann::json StatusJson(const motion_status_t& s) {
  return {{"state", MotionStateName(s.state)},
          {"on_target", s.on_target != 0},
          {"request_id", s.request_id},
          {"activity", s.activity},
          {"progress", s.progress},
          {"queued", s.queued},
          {"last_end", MotionEndName(s.last_end)},
          {"pose_commanded", Array(s.pose_commanded)},
          {"pose_target", Array(s.pose_target)},
          {"pose_measured", Array(s.pose_measured)},
          {"measured_valid", s.measured_valid != 0},
          {"frame", s.frame},
          {"pivot", Array(s.pivot)},
          {"reason", s.reason},
          {"session_id", s.session_id},
          {"utime", s.utime}};
}

nlohmann::json ReplyJson(const motion_reply_t& r) {
  return {{"accepted", r.accepted != 0}, {"code", std::string(ReplyCodeName(r.code))}, {"reason", r.reason},
          {"duration_s", r.duration_s},  {"start_delay_s", r.start_delay_s},           {"request_id", r.request_id}};
}

std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("run --csv " + path + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Until motion `request_id` (0: whatever runs) ends, as the exit code.
int Wait(MotionClient& link, std::int64_t request_id, double timeout_s) {
  const WaitResult r = link.Wait(request_id, timeout_s);
  if (r.outcome != WaitOutcome::kOnTarget) std::fprintf(stderr, "edsp-ctl: %s\n", r.message.c_str());
  switch (r.outcome) {
    case WaitOutcome::kOnTarget: return kDone;
    case WaitOutcome::kHaltedOrStopped: return kInterrupted;
    case WaitOutcome::kFault: return kError;
    case WaitOutcome::kTimedOut: return kTimedOut;
  }
  return kError;
}

void FillPose(const std::string& text, motion_request_t* r) {
  const Vector6 q = ParsePoseText(text).ToVector();
  for (int k = 0; k < 6; ++k) r->pose[k] = q(k);
}

int SendAndReport(MotionClient& link, const motion_request_t& r, const MotionArgs& a, bool wait) {
  const std::optional<motion_reply_t> reply = link.Send(r);
  if (!reply) {
    std::fprintf(stderr, "edsp-ctl: no reply from the planner within the timeout (is its motion service running?)\n");
    return kError;
  }
  if (a.json) std::printf("%s\n", ReplyJson(*reply).dump().c_str());
  if (FamilyOf(reply->code) != ReplyFamily::kDone) {
    std::fprintf(stderr, "edsp-ctl: refused (%s): %s\n", std::string(ReplyCodeName(reply->code)).c_str(),
                 reply->reason.c_str());
    return ExitFor(reply->code);
  }
  if (!a.json) std::printf("planner: %s\n", reply->reason.c_str());
  if (!wait) return kDone;
  const double timeout = a.wait_timeout_s >= 0.0 ? a.wait_timeout_s : reply->start_delay_s + reply->duration_s + 30.0;
  return Wait(link, r.request_id, timeout);
}

int Move(MotionClient& link, const MotionArgs& a, std::int8_t kind) {
  motion_request_t r = link.Request(kind);
  FillPose(a.pose, &r);
  r.relative = a.relative;
  r.frame = a.frame;
  r.speed_m_s = a.speed_m_s;
  r.speed_rad_s = a.speed_rad_s;
  return SendAndReport(link, r, a, kind == motion_request_t::KIND_MOVE && !a.no_wait);
}

// A jog: `step` along one axis, the planner checks the step (motion_request_checks.h).
int Jog(MotionClient& link, const MotionArgs& a) {
  motion_request_t r = link.Request(motion_request_t::KIND_JOG);
  r.pose[JogAxisIndex(a.axis)] = a.step;  // CLI11 took only a known axis
  r.relative = true;
  r.frame = a.frame;
  r.speed_m_s = a.speed_m_s;
  r.speed_rad_s = a.speed_rad_s;
  return SendAndReport(link, r, a, !a.no_wait);
}

int RunProgram(MotionClient& link, const MotionArgs& a) {
  motion_request_t r = link.Request(motion_request_t::KIND_RUN);
  if (a.motions.empty() == a.csv.empty()) throw std::runtime_error("run: give --motions or --csv");
  r.motions = a.motions;
  if (!a.csv.empty()) {
    r.csv_text = FileText(a.csv);
    r.csv_origin = a.csv;
  }
  return SendAndReport(link, r, a, !a.no_wait);
}

int Status(MotionClient& link, const CtlOptions& o, const MotionArgs& a) {
  const std::optional<motion_status_t> s = link.NextStatus(o.timeout_s);
  if (!s) {
    std::fprintf(stderr, "edsp-ctl: no EDSP_MOTION_STATUS within %g s (is the planner running?)\n", o.timeout_s);
    return kError;
  }
  if (a.json) {
    std::printf("%s\n", StatusJson(*s).dump().c_str());
    return kDone;
  }
  std::printf("%s%s  request %lld (%s, %.0f%%, %d queued)  last end: %s  frame %s\n", MotionStateName(s->state),
              s->on_target ? " on target" : "", static_cast<long long>(s->request_id), s->activity.c_str(),
              s->progress * 100.0, s->queued, MotionEndName(s->last_end), s->frame.c_str());
  std::printf("commanded %s\n", fmt::format("{:.6f}", fmt::join(s->pose_commanded, ",")).c_str());
  std::printf("measured  %s%s\n", fmt::format("{:.6f}", fmt::join(s->pose_measured, ",")).c_str(),
              s->measured_valid ? "" : " (not valid)");
  if (!s->reason.empty()) std::printf("reason: %s\n", s->reason.c_str());
  return kDone;
}

void PoseOptions(CLI::App* cmd, MotionArgs* a) {
  cmd->add_option("--pose", a->pose, "X,Y,Z,ROLL,PITCH,YAW (m, rad); --pose=-0.05,... for a leading minus")->required();
  cmd->add_flag("--relative", a->relative, "an increment of the last target, in the frame, about the pivot");
  cmd->add_option("--frame", a->frame, "the work frame the pose is given in (base, home, or one defined)");
  cmd->add_option("--speed-m-s", a->speed_m_s, "the pivot's speed (default and most: [motion] speed_max_m_s)");
  cmd->add_option("--speed-rad-s", a->speed_rad_s, "the rotation's speed (most: [motion] speed_max_rad_s)");
  cmd->add_flag("--json", a->json, "print the reply as JSON");
}

void WaitOptions(CLI::App* cmd, MotionArgs* a) {
  cmd->add_flag("--no-wait", a->no_wait, "return once accepted");
  cmd->add_option("--timeout-s", a->wait_timeout_s, "give up waiting for on-target after this (exit 3)");
}

// The reply alone, never as JSON (the commands that take no --json).
MotionArgs Quiet(const MotionArgs& a) {
  MotionArgs quiet = a;
  quiet.json = false;
  return quiet;
}

// One row per command: its name and help, its own options (the common
// ones are added to each), and what it sends or reads. A new command is a
// row here.
struct MotionCommand {
  const char* name;
  const char* description;
  void (*options)(CLI::App* cmd, MotionArgs* a);
  int (*run)(MotionClient& link, const CtlOptions& o, const MotionArgs& a);
};

const MotionCommand kMotionCommands[] = {
    {"move", "move to a pose (waits until on target)",
     [](CLI::App* cmd, MotionArgs* a) {
       PoseOptions(cmd, a);
       WaitOptions(cmd, a);
     },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       return Move(link, a, motion_request_t::KIND_MOVE);
     }},
    {"check", "check a move whole; nothing moves", PoseOptions,
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       return Move(link, a, motion_request_t::KIND_CHECK);
     }},
    {"jog", "a small relative move along one axis, about the pivot (waits until on target)",
     [](CLI::App* cmd, MotionArgs* a) {
       cmd->add_option("--axis", a->axis, "x, y, z (m) or roll, pitch, yaw (rad), of the frame")
           ->required()
           ->check(CLI::IsMember(std::vector<std::string>(std::begin(kJogAxes), std::end(kJogAxes))));
       cmd->add_option("--step", a->step, "the step (m or rad, signed): at most 0.01 (10 mm, 10 mrad)")->required();
       cmd->add_option("--frame", a->frame, "the work frame whose axis it is (base, home, or one defined)");
       cmd->add_option("--speed-m-s", a->speed_m_s, "the pivot's speed (default and most: [motion] speed_max_m_s)");
       cmd->add_option("--speed-rad-s", a->speed_rad_s, "the rotation's speed (most: [motion] speed_max_rad_s)");
       cmd->add_flag("--json", a->json, "print the reply as JSON");
       WaitOptions(cmd, a);
     },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) { return Jog(link, a); }},
    {"run", "run named motions or a trajectory CSV (waits until on target)",
     [](CLI::App* cmd, MotionArgs* a) {
       cmd->add_option("--motions", a->motions, "Lz,Lx,... M1…M999, calibration");
       cmd->add_option("--csv", a->csv, "a trajectory CSV (sent whole)");
       cmd->add_flag("--json", a->json, "print the reply as JSON");
       WaitOptions(cmd, a);
     },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) { return RunProgram(link, a); }},
    {"halt", "decelerate along the path within the acceleration limit, and hold", [](CLI::App*, MotionArgs*) {},
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       return SendAndReport(link, link.Request(motion_request_t::KIND_HALT), Quiet(a), false);
     }},
    {"stop", "the shortest stop the legs allow, and hold", [](CLI::App*, MotionArgs*) {},
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       return SendAndReport(link, link.Request(motion_request_t::KIND_STOP), Quiet(a), false);
     }},
    {"wait", "wait until on target (0), halted or stopped (4), timed out (3)",
     [](CLI::App* cmd, MotionArgs* a) { cmd->add_option("--timeout-s", a->wait_timeout_s, "seconds (default 60)"); },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       return Wait(link, 0, a.wait_timeout_s >= 0.0 ? a.wait_timeout_s : 60.0);
     }},
    {"status", "the motion service's state, poses, frame and pivot",
     [](CLI::App* cmd, MotionArgs* a) { cmd->add_flag("--json", a->json, "as JSON"); }, Status},
    {"frame", "define a work frame: a pose in {B}",
     [](CLI::App* cmd, MotionArgs* a) {
       cmd->add_option("name", a->frame, "its name")->required();
       cmd->add_option("--pose", a->pose, "X,Y,Z,ROLL,PITCH,YAW of the frame in {B}")->required();
     },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       motion_request_t r = link.Request(motion_request_t::KIND_FRAME);
       r.frame = a.frame;
       FillPose(a.pose, &r);
       return SendAndReport(link, r, Quiet(a), false);
     }},
    {"pivot", "set the pivot point c in {M} that moves turn about",
     [](CLI::App* cmd, MotionArgs* a) { cmd->add_option("--point", a->point, "X,Y,Z (m) in {M}")->required(); },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       motion_request_t r = link.Request(motion_request_t::KIND_PIVOT);
       const Vector3 c = ParsePointText(a.point);
       for (int k = 0; k < 3; ++k) r.point[k] = c(k);
       return SendAndReport(link, r, Quiet(a), false);
     }},
    {"limits", "set the moves' default speeds and accelerations (within [motion])",
     [](CLI::App* cmd, MotionArgs* a) {
       cmd->add_option("--speed-m-s", a->speed_m_s);
       cmd->add_option("--speed-rad-s", a->speed_rad_s);
       cmd->add_option("--accel-m-s2", a->accel_m_s2);
       cmd->add_option("--accel-rad-s2", a->accel_rad_s2);
     },
     [](MotionClient& link, const CtlOptions&, const MotionArgs& a) {
       motion_request_t r = link.Request(motion_request_t::KIND_LIMITS);
       r.speed_m_s = a.speed_m_s, r.speed_rad_s = a.speed_rad_s;
       r.accel_m_s2 = a.accel_m_s2, r.accel_rad_s2 = a.accel_rad_s2;
       return SendAndReport(link, r, Quiet(a), false);
     }},
};

}  // namespace

void AddMotionCommands(CLI::App* app, CtlOptions* o, MotionArgs* a) {
  for (const MotionCommand& command : kMotionCommands) {
    CLI::App* cmd = app->add_subcommand(command.name, command.description);
    command.options(cmd, a);
    AddCommonOptions(cmd, o);
  }
}

bool RunMotionCommand(const CLI::App& app, const CtlOptions& o, const MotionArgs& a, int* exit_code) {
  for (const MotionCommand& command : kMotionCommands) {
    if (!app.got_subcommand(command.name)) continue;
    MotionClient link(Transport(o), GivenSession(o), o.timeout_s, OperatorName(o));
    *exit_code = command.run(link, o, a);
    return true;
  }
  return false;
}

}  // namespace edsp::ctl
