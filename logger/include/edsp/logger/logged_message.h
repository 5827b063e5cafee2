#pragma once
// A log event decoded as the edsp message its channel carries, for readers
// that follow a few channels of a recording (the dwell table, the
// measurement export, the cueing scores). A setpoint recorded in the older
// layout (pose_setpoint_v1_t, before setpoints carried their phase) reads
// as today's, its phase taken from the label the planners of those logs
// wrote: what a reader decides by is the same for old and new logs.

#include <cstdint>
#include <string>

#include "edsp/logger/log_reader.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/decode.h"

namespace edsp {

// True if the event holds a valid Msg (decoded into *msg).
template <typename Msg>
bool DecodeEvent(const LogEvent& event, Msg* msg) {
  return DecodeUntrusted(msg, event.data.data(), event.data.size());
}

// The same for a setpoint of either layout.
bool DecodeEvent(const LogEvent& event, pose_setpoint_t* setpoint);

// The phase an older planner meant by its label: "cueing", "…/dwell k",
// "hold" (nothing played yet), anything else a move.
std::int8_t PhaseOfLegacyLabel(const std::string& trajectory);

}  // namespace edsp
