#include "edsp/sim/stack_simulation.h"

#include <cmath>
#include <stdexcept>

namespace edsp {

namespace {

RigParameters RigFor(const PlatformConfig& nominal, const StackOptions& options) {
  return options.rig ? *options.rig : IdealRig(nominal);
}

KinematicsNodeOptions KinematicsOptions(const StackOptions& o) {
  KinematicsNodeOptions k;
  k.pr_mode = o.pr_mode;
  k.session_id = o.session_id;
  k.calibration = o.calibration;
  return k;
}

BridgeOptions BridgeOptionsFor(const StackOptions& o) {
  BridgeOptions b;
  b.session_id = o.session_id;
  return b;
}

InProcessRigBackend* Activated(InProcessRigBackend* backend, const PlatformConfig& config) {
  std::string error;
  if (!backend->Configure(config, &error) || !backend->Activate(&error)) {
    throw std::runtime_error("virtual rig backend: " + error);
  }
  return backend;
}

}  // namespace

StackSimulation::StackSimulation(const PlatformConfig& nominal,
                                 std::unique_ptr<TrajectorySequence> trajectory,
                                 StackOptions options)
    : options_(std::move(options)),
      planner_(PlatformModel(nominal), std::move(trajectory), options_.session_id),
      kinematics_(PlatformModel(nominal), KinematicsOptions(options_)),
      rig_(RigFor(nominal, options_)),
      backend_(&rig_),
      bridge_(PlatformModel(nominal), Activated(&backend_, nominal), BridgeOptionsFor(options_)),
      now_utime_(options_.start_utime) {
  planner_.Start(now_utime_);
}

StackSample StackSimulation::Step() {
  StackSample s;
  fault_t fault;
  s.setpoint = planner_.Step(now_utime_);
  s.command_valid = kinematics_.HandleSetpoint(s.setpoint, now_utime_, &s.command, &fault);
  if (!s.command_valid) {
    faults_.push_back(fault);
  } else if (!bridge_.HandleCommand(s.command, now_utime_, &fault)) {
    faults_.push_back(fault);
  }
  if (bridge_.Cycle(now_utime_, &s.legs, &fault)) faults_.push_back(fault);
  if (!rig_.Advance(options_.cycle_s)) {
    throw std::runtime_error("virtual rig: the platform pose could not be found");
  }
  now_utime_ += std::llround(options_.cycle_s * 1e6);
  s.truth = rig_.Truth(now_utime_);
  s.tracker_due = rig_.TrackerSample(now_utime_, &s.tracker);
  return s;
}

bool StackSimulation::Finished() const { return planner_.Finished(now_utime_); }

}  // namespace edsp
