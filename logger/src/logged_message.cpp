#include "edsp/logger/logged_message.h"

#include <algorithm>

#include "edsp/pose_setpoint_v1_t.hpp"

namespace edsp {

bool DecodeEvent(const LogEvent& event, pose_setpoint_t* setpoint) {
  if (DecodeUntrusted(setpoint, event.data.data(), event.data.size())) return true;
  pose_setpoint_v1_t old;
  if (!DecodeUntrusted(&old, event.data.data(), event.data.size())) return false;
  setpoint->utime = old.utime;
  setpoint->seq = old.seq;
  setpoint->session_id = old.session_id;
  std::copy(std::begin(old.pose), std::end(old.pose), std::begin(setpoint->pose));
  std::copy(std::begin(old.velocity), std::end(old.velocity), std::begin(setpoint->velocity));
  std::copy(std::begin(old.acceleration), std::end(old.acceleration), std::begin(setpoint->acceleration));
  setpoint->segment = old.segment;
  setpoint->phase = PhaseOfLegacyLabel(old.trajectory);
  setpoint->trajectory = std::move(old.trajectory);
  return true;
}

std::int8_t PhaseOfLegacyLabel(const std::string& trajectory) {
  if (trajectory == "cueing") return pose_setpoint_t::PHASE_CUEING;
  if (trajectory == "hold") return pose_setpoint_t::PHASE_HOLD;
  if (trajectory.find("/dwell") != std::string::npos) return pose_setpoint_t::PHASE_DWELL;
  return pose_setpoint_t::PHASE_MOVE;
}

}  // namespace edsp
