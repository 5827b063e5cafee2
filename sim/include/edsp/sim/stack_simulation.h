#pragma once
// The whole stack composed in one process on a deterministic clock: planner
// → kinematics node → actuator bridge → virtual rig, one cycle per call, no
// bus. The same library classes the processes run, so what it shows about
// accuracy holds for the live stack.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/kinematics/kinematics_node.h"
#include "edsp/planner/motion_service.h"
#include "edsp/planner/planner.h"
#include "edsp/rig/virtual_rig.h"

namespace edsp {

struct StackOptions {
  PrMode pr_mode = PrMode::kSigned;
  std::int64_t session_id = 1;
  double cycle_s = 1e-3;                                     // 1 kHz
  std::int64_t start_utime = 1700000000000000;               // fixed: runs are reproducible
  std::optional<RigParameters> rig;                          // default: IdealRig(nominal)
  std::optional<calibration::CalibrationModel> calibration;  // the kinematics applies it
};

// Every field zero until set: the messages are lcm-gen's plain structs, and
// a field the simulation does not set (a held setpoint's velocity) must not
// carry whatever the stack held before.
struct StackSample {
  pose_setpoint_t setpoint{};
  bool command_valid = false;
  leg_command_t command{};
  leg_state_t legs{};
  rig_truth_t truth{};
  bool tracker_due = false;
  tracker_point_t tracker{};
};

class StackSimulation {
 public:
  // Throws std::invalid_argument if the trajectory leaves the workspace.
  StackSimulation(const PlatformConfig& nominal, std::unique_ptr<TrajectorySequence> trajectory, StackOptions options);
  // The planner's motion service instead of a trajectory: it holds home and
  // moves as requests (motion()) ask, seeing the bridge's leg states and
  // the kinematics' measured pose as the live planner does.
  StackSimulation(const PlatformConfig& nominal, StackOptions options);

  // One cycle. Throws std::runtime_error if the rig's pose cannot be found.
  StackSample Step();
  // The trajectory played, or (with the motion service) nothing moving.
  bool Finished() const;
  std::int64_t now_utime() const { return now_utime_; }

  const std::vector<fault_t>& faults() const { return faults_; }
  const PlatformModel& nominal_model() const { return kinematics_.model(); }
  const TrajectorySequence& trajectory() const { return planner_->sequence(); }
  // The motion service (the second constructor only).
  MotionService& motion() { return *service_; }
  VirtualRig& rig() { return rig_; }
  // The kinematics node, for what an operator does to it while the stack
  // runs (a live calibration switch, a PR mode switch).
  KinematicsNode& kinematics() { return kinematics_; }

 private:
  void BlendTheCalibrationInAtHome();  // before the first motion, when a calibration is in force
  void RunCycle(StackSample* s);       // its setpoint through kinematics, bridge and drives
  void AdvanceRig();                   // one cycle of the rig's physics and the clock
  void InformService(const leg_state_t& legs);

  StackOptions options_;
  std::optional<Planner> planner_;
  std::optional<MotionService> service_;
  KinematicsNode kinematics_;
  VirtualRig rig_;
  InProcessRigBackend backend_;
  ActuatorBridge bridge_;
  std::int64_t now_utime_;
  std::int64_t cycles_ = 0;
  std::vector<fault_t> faults_;
};

}  // namespace edsp
