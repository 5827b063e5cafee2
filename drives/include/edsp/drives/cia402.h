#pragma once
// CiA 402 (IEC 61800-7-201) as edsp's drives speak it: the power state
// machine driven by the controlword (6040h) and shown in the statusword
// (6041h), the objects of cyclic synchronous position (CSP) mode, and the
// master's side: which controlword moves a drive towards the state it wants.
// The same semantics whether the image is served by the virtual drives, a
// Modbus TCP server or an EtherCAT master (docs/drives.md).

#include <cstdint>
#include <string_view>

namespace edsp::cia402 {

// Object dictionary indices of the process image (docs/drives.md).
inline constexpr std::uint16_t kErrorCode = 0x603F;
inline constexpr std::uint16_t kControlword = 0x6040;
inline constexpr std::uint16_t kStatusword = 0x6041;
inline constexpr std::uint16_t kModesOfOperation = 0x6060;
inline constexpr std::uint16_t kModesOfOperationDisplay = 0x6061;
inline constexpr std::uint16_t kPositionActual = 0x6064;
inline constexpr std::uint16_t kFollowingErrorWindow = 0x6065;
inline constexpr std::uint16_t kVelocityActual = 0x606C;
inline constexpr std::uint16_t kTargetPosition = 0x607A;
inline constexpr std::uint16_t kVelocityOffset = 0x60B1;

// Modes of operation (6060h): the only one edsp commands.
inline constexpr std::int8_t kModeCyclicSynchronousPosition = 8;

enum class State : std::uint8_t {
  kNotReadyToSwitchOn,
  kSwitchOnDisabled,
  kReadyToSwitchOn,
  kSwitchedOn,
  kOperationEnabled,
  kQuickStopActive,
  kFaultReactionActive,
  kFault,
};

// The device control commands a controlword encodes (bits 0-3 and 7).
enum class Command : std::uint8_t {
  kShutdown,          // xxxx 0xxx x110
  kSwitchOn,          // 0xxx 0111
  kEnableOperation,   // 0xxx 1111
  kDisableOperation,  // 0xxx 0111 in operation enabled (the same bits as switch on)
  kDisableVoltage,    // 0xxx xx0x
  kQuickStop,         // 0xxx x01x
  kFaultReset,        // a rising edge of bit 7
};

// Statusword bits beyond the state (6041h).
inline constexpr std::uint16_t kStatusVoltageEnabled = 1u << 4;
inline constexpr std::uint16_t kStatusWarning = 1u << 7;
inline constexpr std::uint16_t kStatusRemote = 1u << 9;
inline constexpr std::uint16_t kStatusTargetReached = 1u << 10;
inline constexpr std::uint16_t kStatusFollowingError = 1u << 13;  // CSP: beyond 6065h
inline constexpr std::uint16_t kControlFaultReset = 1u << 7;

std::string_view StateName(State state);

// The controlword a master writes for `command` (bit 7 set for a fault
// reset: the drive acts on its rising edge, so the master clears it first).
std::uint16_t ControlwordFor(Command command);

// The state a statusword shows (bits 0-3, 5, 6 as the standard masks them).
State StateOfStatusword(std::uint16_t statusword);
// The state bits of `state`, with voltage enabled where the state has it.
std::uint16_t StatusBits(State state);

// The drive's side of the state machine. Transition numbers are the
// standard's (2-16); 0 means the controlword asked for nothing this state
// accepts, and the drive stays where it is.
class DriveStateMachine {
 public:
  // Power-up (transitions 0 and 1 happen on their own): switch on disabled.
  DriveStateMachine() = default;

  State state() const { return state_; }
  // The master's controlword of this cycle; returns the transition taken.
  int OnControlword(std::uint16_t controlword);
  // The drive detected a fault (13), with its error code (603Fh): the
  // fault reaction runs (the drive brakes) until FaultReactionDone (14).
  void RaiseFault(std::uint16_t error_code);
  void FaultReactionDone();
  // A quick stop has brought the axis to rest (12, quick stop option 2).
  void QuickStopDone();

  // The drive follows its target only here.
  bool FollowsTarget() const { return state_ == State::kOperationEnabled; }
  std::uint16_t error_code() const { return error_code_; }
  std::uint16_t statusword() const { return StatusBits(state_) | kStatusRemote; }

 private:
  State state_ = State::kSwitchOnDisabled;
  std::uint16_t error_code_ = 0;
  bool fault_reset_bit_ = false;  // bit 7 of the last controlword: resets act on its edge
};

// The master's side: the controlword that moves a drive now in `current`
// one transition towards operation enabled (from fault: a fault reset,
// then on). `previous` is the controlword written last cycle, so a fault
// reset is always an edge.
std::uint16_t ControlwordTowardOperation(State current, std::uint16_t previous);

}  // namespace edsp::cia402
