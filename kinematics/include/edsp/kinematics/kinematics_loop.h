#pragma once
// The kinematics node on a bus: EDSP_SETPOINT, EDSP_LEG_STATE and the
// operator's EDSP_PR_MODE and EDSP_CALIBRATION in; EDSP_LEG_COMMAND,
// EDSP_PLATFORM_STATE (every 10th leg state: 1 kHz in, 100 Hz out),
// EDSP_CONFIG (latched, once a second), EDSP_REPLY (the operator's
// answers), EDSP_FAULT and EDSP_STATUS out. The
// process's main only parses options, builds the KinematicsNode and runs
// this; tests run it on an in-process bus.

#include <cstdint>
#include <functional>
#include <string>

#include "edsp/kinematics/kinematics_node.h"
#include "edsp/node/node_reporting.h"
#include "edsp/transport/bus.h"

namespace edsp {

struct KinematicsLoopOptions {
  std::string config_text;        // the config file's text, carried on EDSP_CONFIG
  bool replay = false;            // setpoints from a log: judged by their own clock
  int leg_state_decimation = 10;  // one platform state per this many leg states
};

class KinematicsLoop {
 public:
  // Set-up: subscribes and advertises on `bus` (may throw TransportError)
  // and says which calibration is in force (EDSP_FAULT info, stderr). The
  // bus and the node must outlive the loop; its handlers point at it: no
  // copy, no move, and no Bus::Handle after it is gone.
  KinematicsLoop(Bus& bus, KinematicsNode& kinematics, KinematicsLoopOptions options);
  KinematicsLoop(const KinematicsLoop&) = delete;
  KinematicsLoop& operator=(const KinematicsLoop&) = delete;

  // EDSP_CONFIG when a second has passed, undecodable input reported, the
  // status. Call at least every 100 ms.
  void Poll(std::int64_t now_utime);
  // Handles the bus and polls until `stop` says so.
  void Run(const std::function<bool()>& stop);

 private:
  void OnSetpoint(const pose_setpoint_t& setpoint);
  void OnLegState(const leg_state_t& legs);
  void ReportCalibration();
  void Answer(const RequestService<reply_t>::Answer& answer);  // on EDSP_REPLY; a switch made, on stderr

  Bus& bus_;
  KinematicsNode& kinematics_;
  KinematicsLoopOptions options_;
  Bus::Publisher<leg_command_t> commands_;
  Bus::Publisher<platform_state_t> states_;
  Bus::Publisher<platform_config_t> config_out_;
  Bus::Publisher<reply_t> replies_;
  NodeReporting reporting_;
  std::int64_t leg_states_ = 0;
  std::int64_t next_config_utime_ = 0;
};

}  // namespace edsp
