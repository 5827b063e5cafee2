#pragma once
// edsp-ctl's motion commands: requests to the planner's motion service
// (EDSP_MOTION_REQUEST), its reply (EDSP_MOTION_REPLY) and its status
// (EDSP_MOTION_STATUS). Exit codes, as docs/interfaces.md §7 contracts:
// 0 done, 2 refused (the reason on stderr), 3 timed out, 4 halted or
// stopped by another request, 1 any other error.
#include <string>

#include <CLI/CLI.hpp>

#include "ctl_session.h"

namespace edsp::ctl {

struct MotionArgs {
  std::string pose, point, frame, motions, csv, axis;
  bool relative = false, no_wait = false, json = false;
  double step = 0.0, speed_m_s = 0.0, speed_rad_s = 0.0, accel_m_s2 = 0.0, accel_rad_s2 = 0.0;
  double wait_timeout_s = -1.0;  // < 0: the motion's duration and 30 s beside
};

// Adds move, check, jog, run, halt, stop, wait, status, frame, pivot and limits
// to `app` (one table, motion_commands.cpp's kMotionCommands);
// RunMotionCommand runs whichever was given (false: none was).
void AddMotionCommands(CLI::App* app, CtlOptions* options, MotionArgs* args);
bool RunMotionCommand(const CLI::App& app, const CtlOptions& options, const MotionArgs& args, int* exit_code);

}  // namespace edsp::ctl
