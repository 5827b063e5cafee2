#pragma once
// The actuator bridge's logic, free of any bus: leg commands in, drive
// setpoints out, encoders back as leg states. Safety first: it forwards only
// commands it can validate (session, finite, within stroke, no jump from the
// last valid target), and when commands stop coming (stale) it holds the last
// valid position and stays latched there until explicitly re-armed.

#include <cstdint>
#include <string>

#include "edsp/actuator_bridge/drive_backend.h"
#include "edsp/node/fault.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"

namespace edsp {

struct BridgeOptions {
  std::string node_name = "actuator_bridge";
  std::int64_t session_id = 0;       // commands from any other session are refused
  std::int64_t stale_us = 50000;     // no valid command for this long: hold
  double max_leg_speed_m_s = -1.0;   // faster changes are jumps; < 0: the config's
                                     // [limits] leg_speed_max_m_s
};

class ActuatorBridge {
 public:
  // The backend must outlive the bridge. Starts holding the current position.
  ActuatorBridge(PlatformModel model, DriveBackend* backend, BridgeOptions options);

  // True: the command becomes the target and is written to the drives at
  // once. False: *fault says why it was refused.
  bool HandleCommand(const leg_command_t& command, std::int64_t now_utime, fault_t* fault);

  // One drive cycle: hold if the target went stale, write it, read the drives.
  // Returns true and fills *fault when a new fault arose this cycle.
  bool Cycle(std::int64_t now_utime, leg_state_t* state, fault_t* fault);

  // After a stale hold the bridge refuses every command until an operator
  // re-arms it (the stream may come back anywhere; resuming by itself when the
  // trajectory happens to pass the held pose would start the platform with a
  // jerk). After Rearm(), commands resume subject to the jump guard, i.e. once
  // they continue from the held position.
  void Rearm();
  bool latched() const { return latched_; }
  bool holding() const { return holding_; }
  std::int64_t accepted() const { return accepted_; }
  std::int64_t rejected() const { return rejected_; }

 private:
  fault_t Fault(FaultCode code, std::string reason, std::int64_t now_utime) const;
  bool Reject(FaultCode code, std::string reason, std::int64_t now_utime, fault_t* fault);

  PlatformModel model_;
  DriveBackend* backend_;
  BridgeOptions options_;
  DriveSetpoint target_;             // what the drives are told
  Vector6 target_length_m_;
  std::int64_t target_utime_ = -1;   // receipt time of the last valid command
  std::int64_t last_basis_utime_ = 0; // its planner time (setpoint_utime)
  std::int64_t last_command_seq_ = 0;
  bool holding_ = true;
  bool hold_reported_ = true;        // start holding without a fault
  bool backend_ok_ = true;           // faults are raised on the transition only
  bool latched_ = false;             // held after stale input: needs Rearm()
  std::int64_t state_seq_ = 0;
  std::int64_t accepted_ = 0;
  std::int64_t rejected_ = 0;
  DriveFeedback feedback_;
};

}  // namespace edsp
