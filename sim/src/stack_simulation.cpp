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

StackSimulation::StackSimulation(const PlatformConfig& nominal, std::unique_ptr<TrajectorySequence> trajectory,
                                 StackOptions options)
    : options_(std::move(options)),
      planner_(std::in_place, PlatformModel(nominal), std::move(trajectory), options_.session_id),
      kinematics_(PlatformModel(nominal), KinematicsOptions(options_)),
      rig_(RigFor(nominal, options_)),
      backend_(&rig_),
      bridge_(PlatformModel(nominal), Activated(&backend_, nominal), BridgeOptionsFor(options_)),
      now_utime_(options_.start_utime) {
  BlendTheCalibrationInAtHome();
  planner_->Start(now_utime_);
}

StackSimulation::StackSimulation(const PlatformConfig& nominal, StackOptions options)
    : options_(std::move(options)),
      kinematics_(PlatformModel(nominal), KinematicsOptions(options_)),
      rig_(RigFor(nominal, options_)),
      backend_(&rig_),
      bridge_(PlatformModel(nominal), Activated(&backend_, nominal), BridgeOptionsFor(options_)),
      now_utime_(options_.start_utime) {
  BlendTheCalibrationInAtHome();
  MotionServiceOptions service;
  service.session_id = options_.session_id;
  service_.emplace(PlatformModel(nominal), service);
}

void StackSimulation::BlendTheCalibrationInAtHome() {
  // As the live group, whose bridge reads the drives from before the first
  // command, a calibration in force at start blends in from where they hold
  // (the rig's at the nominal model's home command). The platform holds
  // home meanwhile, and the run begins calibrated: an operator who starts
  // the motions once the calibration is in. The wait is whole seconds, so
  // the tracker samples the motions on the grid a run without the
  // calibration has (runs with and without it compare sample by sample).
  // Without one, nothing to wait for.
  if (!options_.calibration) return;
  const std::int64_t began_utime = now_utime_;
  const std::int64_t cycle_us = std::llround(options_.cycle_s * 1e6);
  leg_state_t first_reading{};
  fault_t fault{};
  if (bridge_.Cycle(now_utime_ - cycle_us, &first_reading, &fault)) faults_.push_back(fault);
  kinematics_.NoteDrives(first_reading);
  const auto held_long_enough = [&] {
    const std::int64_t held_us = now_utime_ - began_utime;
    return !kinematics_.calibration_blending() && held_us > 0 && held_us % 1000000 < cycle_us;
  };
  StackSample held;
  held.setpoint.session_id = options_.session_id;
  held.setpoint.trajectory = "calibration blending in at home";
  const Vector6 q = kinematics_.model().home_pose().ToVector();
  for (int k = 0; k < 6; ++k) held.setpoint.pose[k] = q(k);
  do {
    held.setpoint.utime = now_utime_;
    ++held.setpoint.seq;
    RunCycle(&held);
    AdvanceRig();
  } while (!held_long_enough() && faults_.empty());
}

StackSample StackSimulation::Step() {
  StackSample s;
  s.setpoint = planner_ ? planner_->Step(now_utime_) : service_->Step(now_utime_);
  RunCycle(&s);
  if (service_) InformService(s.legs);
  AdvanceRig();
  s.truth = rig_.Truth(now_utime_);
  s.tracker_due = rig_.TrackerSample(now_utime_, &s.tracker);
  return s;
}

void StackSimulation::RunCycle(StackSample* s) {
  fault_t fault;
  s->command_valid = kinematics_.HandleSetpoint(s->setpoint, now_utime_, &s->command, &fault);
  if (!s->command_valid) {
    faults_.push_back(fault);
  } else if (!bridge_.HandleCommand(s->command, now_utime_, &fault)) {
    faults_.push_back(fault);
  }
  if (bridge_.Cycle(now_utime_, &s->legs, &fault)) faults_.push_back(fault);
  kinematics_.NoteDrives(s->legs);
}

void StackSimulation::AdvanceRig() {
  if (!rig_.Advance(options_.cycle_s)) {
    throw std::runtime_error("virtual rig: the platform pose could not be found");
  }
  now_utime_ += std::llround(options_.cycle_s * 1e6);
}

void StackSimulation::InformService(const leg_state_t& legs) {
  // As the live group: leg states at 1 kHz, the measured pose at 100 Hz.
  constexpr int kPlatformStateDecimation = 10;
  service_->OnLegState(legs, now_utime_);
  if (++cycles_ % kPlatformStateDecimation != 0) return;
  platform_state_t state;
  fault_t fault;
  if (kinematics_.HandleLegState(legs, now_utime_, &state, &fault)) service_->OnPlatformState(state, now_utime_);
}

bool StackSimulation::Finished() const { return planner_ ? planner_->Finished(now_utime_) : !service_->busy(); }

}  // namespace edsp
