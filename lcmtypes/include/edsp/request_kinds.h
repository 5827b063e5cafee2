#pragma once
// A motion request's kind (motion_request_t.KIND_*) by name, once: the
// planner names a refusal and chooses where to plan from it, edsp-ctl and
// Python take the kinds' names and numbers from it and the web panel gets
// them from the server (docs/extending.md, "A request"). A new kind is a
// constant in motion_request_t.lcm and a row here.

#include <cstdint>
#include <string_view>

#include "edsp/motion_request_t.hpp"

namespace edsp {

struct RequestKindRow {
  std::int8_t kind;
  std::string_view name;  // as edsp-ctl's command, Python's KIND_<NAME> and the panel spell it
  // Plans a path checked whole (milliseconds of work): the planner does it
  // beside its 1 kHz cycle, never inside it.
  bool plans_path;
};

inline constexpr RequestKindRow kRequestKinds[] = {
    {motion_request_t::KIND_MOVE, "move", true},     {motion_request_t::KIND_CHECK, "check", true},
    {motion_request_t::KIND_RUN, "run", true},       {motion_request_t::KIND_HALT, "halt", false},
    {motion_request_t::KIND_STOP, "stop", false},    {motion_request_t::KIND_FRAME, "frame", false},
    {motion_request_t::KIND_PIVOT, "pivot", false},  {motion_request_t::KIND_LIMITS, "limits", false},
    {motion_request_t::KIND_ENGAGE, "engage", true}, {motion_request_t::KIND_DISENGAGE, "disengage", true},
    {motion_request_t::KIND_JOG, "jog", true},
};

// The row of a kind as it came off the wire; nullptr for a kind this build
// does not know (a newer client's).
constexpr const RequestKindRow* FindRequestKind(std::int8_t wire) {
  for (const RequestKindRow& row : kRequestKinds) {
    if (row.kind == wire) return &row;
  }
  return nullptr;
}

// The row of a kind by its name; nullptr when none is called that.
constexpr const RequestKindRow* FindRequestKind(std::string_view name) {
  for (const RequestKindRow& row : kRequestKinds) {
    if (row.name == name) return &row;
  }
  return nullptr;
}

}  // namespace edsp
