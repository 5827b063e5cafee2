#pragma once
// The kinematics node's logic, free of any bus (the edsp-kinematics process
// wires it to edsp::Bus): setpoint → leg command with PR compensation in the
// configured (live-switchable) mode; encoder feedback → platform state by
// forward kinematics with PR; the platform config message. A setpoint it
// cannot validate is never forwarded: it yields a fault instead.

#include <cstdint>
#include <string>

#include "edsp/node/fault.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/platform_config_t.hpp"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

struct KinematicsNodeOptions {
  std::string node_name = "kinematics";
  PrMode pr_mode = PrMode::kSigned;
  std::int64_t session_id = 0;   // setpoints from any other session are refused
  std::int64_t stale_us = 50000; // setpoints older than this are refused
};

class KinematicsNode {
 public:
  KinematicsNode(PlatformModel model, KinematicsNodeOptions options);

  // True: *command is the leg command for the setpoint. False: *fault says why.
  bool HandleSetpoint(const pose_setpoint_t& setpoint, std::int64_t now_utime,
                      leg_command_t* command, fault_t* fault);

  // True: *state is the pose the encoders imply. False: *fault says why.
  bool HandleLegState(const leg_state_t& legs, std::int64_t now_utime, platform_state_t* state,
                      fault_t* fault);

  // The config latched on EDSP_CONFIG; `config_toml` is the file's text.
  platform_config_t ConfigMessage(std::int64_t now_utime, const std::string& config_toml);

  void set_pr_mode(PrMode mode) { options_.pr_mode = mode; }
  PrMode pr_mode() const { return options_.pr_mode; }
  const PlatformModel& model() const { return model_; }

 private:
  fault_t Fault(FaultCode code, std::string reason, std::int64_t now_utime,
                const char* channel) const;

  PlatformModel model_;
  KinematicsNodeOptions options_;
  std::int64_t command_seq_ = 0;
  std::int64_t state_seq_ = 0;
  std::int64_t config_seq_ = 0;
  Pose last_target_;
  Pose last_estimate_;
};

}  // namespace edsp
