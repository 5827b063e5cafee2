#pragma once
// A CSP drive as a drive simulator serves it: the CiA 402 state machine
// over an axis that follows its target position while operation is enabled
// and stands (brake) otherwise. It faults as a real drive does: following
// error beyond the window (8611h), lost fieldbus (8130h) while enabled, an
// error its axis raises (a lost encoder), and on demand (tests, a
// simulator's fault injection).
//
// Standing alone it moves its own bounded-speed axis (Step). In a cabinet
// whose axes step together elsewhere (csp_axes.h: the virtual rig's legs),
// a cycle is Advance, then the axes step on every drive's Demand, then each
// drive Senses its axis' reading.

#include <cstdint>

#include "edsp/drives/cia402.h"
#include "edsp/drives/csp_axes.h"
#include "edsp/drives/csp_image.h"

namespace edsp::cia402 {

inline constexpr std::uint16_t kErrorFollowing = 0x8611;
inline constexpr std::uint16_t kErrorFieldbus = 0x8130;

struct SimulatedDriveOptions {
  double max_speed_counts_s = 50e6;              // the axis' speed limit
  std::int32_t following_error_window = 200000;  // 6065h, counts
  double fieldbus_timeout_s = 0.02;              // no command for this long while enabled: fault
};

class SimulatedCspDrive {
 public:
  explicit SimulatedCspDrive(const SimulatedDriveOptions& options = {}, std::int32_t position = 0);

  // The master's latest command (a fieldbus write); resets the fieldbus timer.
  void Command(const CspCommand& command);
  // One drive cycle of `dt_s` seconds on the drive's own clock and axis.
  void Step(double dt_s);
  void InjectFault(std::uint16_t error_code);

  // A cycle on axes stepped elsewhere: the drive's timers (a silent
  // fieldbus faults it) ...
  void Advance(double dt_s);
  // ... what it asks of its axis ...
  AxisDemand Demand() const;
  // ... and where the axis then stands (a following error or the axis'
  // own error faults the drive).
  void Sense(const AxisReading& axis);

  CspFeedback Feedback() const;
  State state() const { return machine_.state(); }

 private:
  SimulatedDriveOptions options_;
  DriveStateMachine machine_;
  CspCommand command_;
  BoundedSpeedAxis own_axis_;
  double position_;
  double velocity_ = 0.0;
  double since_command_s_ = 0.0;
};

}  // namespace edsp::cia402
