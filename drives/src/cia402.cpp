#include "edsp/drives/cia402.h"

namespace edsp::cia402 {
namespace {

constexpr std::uint16_t kSwitchOnBit = 1u << 0;
constexpr std::uint16_t kEnableVoltageBit = 1u << 1;
constexpr std::uint16_t kQuickStopBit = 1u << 2;  // active low: 0 asks for a quick stop
constexpr std::uint16_t kEnableOperationBit = 1u << 3;

// The command bits 0-3 ask for, outside a fault reset; "switch on" and
// "disable operation" share their bits (which one depends on the state).
enum class Request : std::uint8_t { kDisableVoltage, kQuickStop, kShutdown, kSwitchOn, kEnableOperation };

Request RequestOf(std::uint16_t controlword) {
  if ((controlword & kEnableVoltageBit) == 0) return Request::kDisableVoltage;
  if ((controlword & kQuickStopBit) == 0) return Request::kQuickStop;
  if ((controlword & kSwitchOnBit) == 0) return Request::kShutdown;
  return (controlword & kEnableOperationBit) != 0 ? Request::kEnableOperation : Request::kSwitchOn;
}

struct Step {
  State to;
  int transition;
};
constexpr Step kStay{State::kNotReadyToSwitchOn, 0};

// The standard's transitions 2-12 and 16 for one request in one state.
Step Transition(State from, Request request) {
  switch (from) {
    case State::kSwitchOnDisabled: return request == Request::kShutdown ? Step{State::kReadyToSwitchOn, 2} : kStay;
    case State::kReadyToSwitchOn:
      if (request == Request::kSwitchOn || request == Request::kEnableOperation) return {State::kSwitchedOn, 3};
      if (request == Request::kDisableVoltage || request == Request::kQuickStop) return {State::kSwitchOnDisabled, 7};
      return kStay;
    case State::kSwitchedOn:
      if (request == Request::kEnableOperation) return {State::kOperationEnabled, 4};
      if (request == Request::kShutdown) return {State::kReadyToSwitchOn, 6};
      if (request == Request::kDisableVoltage || request == Request::kQuickStop) return {State::kSwitchOnDisabled, 10};
      return kStay;
    case State::kOperationEnabled:
      if (request == Request::kSwitchOn) return {State::kSwitchedOn, 5};  // disable operation
      if (request == Request::kShutdown) return {State::kReadyToSwitchOn, 8};
      if (request == Request::kDisableVoltage) return {State::kSwitchOnDisabled, 9};
      if (request == Request::kQuickStop) return {State::kQuickStopActive, 11};
      return kStay;
    case State::kQuickStopActive:
      if (request == Request::kDisableVoltage) return {State::kSwitchOnDisabled, 12};
      if (request == Request::kEnableOperation) return {State::kOperationEnabled, 16};
      return kStay;
    case State::kNotReadyToSwitchOn:
    case State::kFaultReactionActive:
    case State::kFault: return kStay;  // left on the drive's own events (1, 14) or a fault reset (15)
  }
  return kStay;
}

}  // namespace

std::string_view StateName(State state) {
  switch (state) {
    case State::kNotReadyToSwitchOn: return "not ready to switch on";
    case State::kSwitchOnDisabled: return "switch on disabled";
    case State::kReadyToSwitchOn: return "ready to switch on";
    case State::kSwitchedOn: return "switched on";
    case State::kOperationEnabled: return "operation enabled";
    case State::kQuickStopActive: return "quick stop active";
    case State::kFaultReactionActive: return "fault reaction active";
    case State::kFault: return "fault";
  }
  return "unknown";
}

std::uint16_t ControlwordFor(Command command) {
  switch (command) {
    case Command::kShutdown: return 0x0006;
    case Command::kSwitchOn: return 0x0007;
    case Command::kEnableOperation: return 0x000F;
    case Command::kDisableOperation: return 0x0007;
    case Command::kDisableVoltage: return 0x0000;
    case Command::kQuickStop: return 0x0002;
    case Command::kFaultReset: return kControlFaultReset;
  }
  return 0x0000;
}

State StateOfStatusword(std::uint16_t statusword) {
  // Bits 0-3 and 6 tell every state but three; bit 5 (quick stop) then
  // tells operation enabled from quick stop active.
  switch (statusword & 0x4F) {
    case 0x00: return State::kNotReadyToSwitchOn;
    case 0x40: return State::kSwitchOnDisabled;
    case 0x0F: return State::kFaultReactionActive;
    case 0x08: return State::kFault;
    default: break;
  }
  switch (statusword & 0x6F) {
    case 0x21: return State::kReadyToSwitchOn;
    case 0x23: return State::kSwitchedOn;
    case 0x27: return State::kOperationEnabled;
    case 0x07: return State::kQuickStopActive;
    default: return State::kNotReadyToSwitchOn;  // no state the standard defines: not ready
  }
}

std::uint16_t StatusBits(State state) {
  switch (state) {
    case State::kNotReadyToSwitchOn: return 0x0000;
    case State::kSwitchOnDisabled: return 0x0040;
    case State::kReadyToSwitchOn: return 0x0021 | kStatusVoltageEnabled;
    case State::kSwitchedOn: return 0x0023 | kStatusVoltageEnabled;
    case State::kOperationEnabled: return 0x0027 | kStatusVoltageEnabled;
    case State::kQuickStopActive: return 0x0007 | kStatusVoltageEnabled;
    case State::kFaultReactionActive: return 0x000F | kStatusVoltageEnabled;
    case State::kFault: return 0x0008;
  }
  return 0x0000;
}

int DriveStateMachine::OnControlword(std::uint16_t controlword) {
  const bool reset_bit = (controlword & kControlFaultReset) != 0;
  const bool reset_edge = reset_bit && !fault_reset_bit_;
  fault_reset_bit_ = reset_bit;
  if (state_ == State::kFault) {
    if (!reset_edge) return 0;
    state_ = State::kSwitchOnDisabled;
    error_code_ = 0;
    return 15;
  }
  // Bit 7 set is a fault reset request and nothing else (the standard's
  // commands all have it clear): outside a fault it changes nothing.
  if (reset_bit) return 0;
  const Step step = Transition(state_, RequestOf(controlword));
  if (step.transition == 0) return 0;
  state_ = step.to;
  return step.transition;
}

void DriveStateMachine::RaiseFault(std::uint16_t error_code) {
  if (state_ == State::kFault || state_ == State::kFaultReactionActive) return;  // the first fault's code stays
  state_ = State::kFaultReactionActive;
  error_code_ = error_code;
}

void DriveStateMachine::FaultReactionDone() {
  if (state_ == State::kFaultReactionActive) state_ = State::kFault;
}

void DriveStateMachine::QuickStopDone() {
  if (state_ == State::kQuickStopActive) state_ = State::kSwitchOnDisabled;
}

std::uint16_t ControlwordTowardOperation(State current, std::uint16_t previous) {
  switch (current) {
    case State::kFault:
      // A reset acts on the rising edge of bit 7: clear it first if it is set.
      return (previous & kControlFaultReset) != 0 ? ControlwordFor(Command::kDisableVoltage)
                                                  : ControlwordFor(Command::kFaultReset);
    case State::kNotReadyToSwitchOn:
    case State::kSwitchOnDisabled: return ControlwordFor(Command::kShutdown);
    case State::kReadyToSwitchOn: return ControlwordFor(Command::kSwitchOn);
    case State::kSwitchedOn:
    case State::kOperationEnabled: return ControlwordFor(Command::kEnableOperation);
    case State::kQuickStopActive:
    case State::kFaultReactionActive:
      // Never resume out of a stop the drive is still carrying out: let
      // it end in switch on disabled and go through the sequence again.
      return ControlwordFor(Command::kDisableVoltage);
  }
  return ControlwordFor(Command::kDisableVoltage);
}

}  // namespace edsp::cia402
