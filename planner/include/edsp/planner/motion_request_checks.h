#pragma once
// What a motion request must be on its own, before the motion service acts
// on it: finite numbers, a frame it may define, a pivot within reach, a
// program named one way, limits within the config's. Each check returns
// nothing or why the request is refused (ReplyCode::kInvalid), naming the
// field and the value. The service (motion_service.h) checks the rest, which depends
// on its state: the bridge following, the queue, the frames it knows, the
// path whole.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "edsp/kinematics/types.h"
#include "edsp/motion_request_t.hpp"
#include "edsp/planner/planned_motion.h"

namespace edsp {

// Why a request is refused or must wait, or nothing: what every check of a
// request (here) and of the service's state (motion_service.h) returns.
using Problem = std::optional<std::string>;

// The kind's name (request_kinds.h); "kind N" for one no client should send.
std::string RequestKindName(std::int8_t kind);
// The request's pose field as x, y, z, roll, pitch, yaw.
Vector6 RequestPose(const motion_request_t& r);
// A pose as replies and faults write it: "(x, y, z m; roll, pitch, yaw rad)".
std::string PoseText(const Vector6& q);

// A move's or a check's pose: every value finite.
Problem PoseProblem(const motion_request_t& r);
// A jog's axes, in the order of the pose field, as edsp-ctl and Python name them.
inline constexpr const char* kJogAxes[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
// A jog is small: its step is at most 10 mm (x, y, z) or 10 mrad (roll, pitch, yaw).
inline constexpr double kJogStepMax = 0.01;
// The index of a jog axis in the pose field by its name; -1 for none.
int JogAxisIndex(std::string_view name);
// A jog's pose: exactly one value nonzero (the step along its axis), none
// not finite, the step at most kJogStepMax.
Problem JogProblem(const motion_request_t& r);
// A frame's definition: a new name (not base or home), a finite pose whose
// origin lies within 100 m of {B}.
Problem FrameDefinitionProblem(const motion_request_t& r);
// A pivot: finite, within 10 m of {M}'s origin.
Problem PivotProblem(const motion_request_t& r);
// A run: named motions or a CSV, not both and not neither.
Problem ProgramProblem(const motion_request_t& r);
// The speeds a move asks for (0: `limits`' own), each in [most/1000, most];
// on success `limits` holds them.
Problem SpeedLimitsProblem(const motion_request_t& r, const MoveLimits& most, MoveLimits* limits);
// The same for a limits request's speeds and accelerations.
Problem AllLimitsProblem(const motion_request_t& r, const MoveLimits& most, MoveLimits* limits);

}  // namespace edsp
