#include "edsp/drives/simulated_csp_drive.h"

#include <cmath>

namespace edsp::cia402 {

SimulatedCspDrive::SimulatedCspDrive(const SimulatedDriveOptions& options, std::int32_t position)
    : options_(options), own_axis_(options.max_speed_counts_s, position), position_(position) {}

void SimulatedCspDrive::Command(const CspCommand& command) {
  command_ = command;
  since_command_s_ = 0.0;
  machine_.OnControlword(command.controlword);
}

void SimulatedCspDrive::InjectFault(std::uint16_t error_code) { machine_.RaiseFault(error_code); }

void SimulatedCspDrive::Step(double dt_s) {
  Advance(dt_s);
  Sense(own_axis_.Step(dt_s, Demand()));
}

void SimulatedCspDrive::Advance(double dt_s) {
  since_command_s_ += dt_s;
  if (machine_.FollowsTarget() && since_command_s_ > options_.fieldbus_timeout_s) {
    machine_.RaiseFault(kErrorFieldbus);
  }
}

AxisDemand SimulatedCspDrive::Demand() const {
  AxisDemand demand;
  demand.follow = machine_.FollowsTarget() && command_.mode_of_operation == kModeCyclicSynchronousPosition;
  demand.target = command_.target_position;
  demand.velocity_offset = command_.velocity_offset;
  return demand;
}

void SimulatedCspDrive::Sense(const AxisReading& axis) {
  position_ = axis.position;
  velocity_ = axis.velocity;
  if (axis.error_code != 0) machine_.RaiseFault(axis.error_code);
  if (Demand().follow &&
      std::abs(static_cast<double>(command_.target_position) - position_) > options_.following_error_window) {
    machine_.RaiseFault(kErrorFollowing);
  }
  // The brake holds the axis in every other state; a fault reaction and a
  // quick stop end once it stands (these axes stop within a cycle).
  if (machine_.state() == State::kFaultReactionActive) machine_.FaultReactionDone();
  if (machine_.state() == State::kQuickStopActive) machine_.QuickStopDone();
}

CspFeedback SimulatedCspDrive::Feedback() const {
  CspFeedback f;
  std::uint16_t extra = 0;
  if (machine_.FollowsTarget() && std::abs(static_cast<double>(command_.target_position) - position_) < 0.5) {
    extra |= kStatusTargetReached;
  }
  f.statusword = static_cast<std::uint16_t>(machine_.statusword() | extra);
  f.mode_display = command_.mode_of_operation;
  f.position_actual = static_cast<std::int32_t>(std::lround(position_));
  f.velocity_actual = static_cast<std::int32_t>(std::lround(velocity_));
  f.error_code = machine_.error_code();
  return f;
}

}  // namespace edsp::cia402
