#pragma once
// A setpoint's phase (pose_setpoint_t.PHASE_*) and its name, once: readers
// of setpoints decide by the phase, never by the trajectory label, and
// Python names it (edsp.SetpointPhase). A new phase is a constant in
// pose_setpoint_t.lcm and a row here.

#include <cstdint>
#include <string_view>

#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

struct SetpointPhaseRow {
  std::int8_t phase;
  std::string_view name;
};

inline constexpr SetpointPhaseRow kSetpointPhases[] = {
    {pose_setpoint_t::PHASE_HOLD, "hold"},
    {pose_setpoint_t::PHASE_MOVE, "move"},
    {pose_setpoint_t::PHASE_DWELL, "dwell"},
    {pose_setpoint_t::PHASE_CUEING, "cueing"},
};

}  // namespace edsp
