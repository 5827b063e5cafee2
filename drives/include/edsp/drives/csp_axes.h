#pragma once
// What stands behind a drive cabinet's six CiA 402 state machines: the axes
// they move. The simulator's own (each follows its target at a bounded
// speed) or another process's physics (the virtual rig's legs behind its
// process image: drive_sim/). A drive cycle asks each axis for what its
// drive demands and reads back where it stands, in the drive's counts.

#include <array>
#include <cstdint>

namespace edsp::cia402 {

inline constexpr int kCabinetDrives = 6;

// What a drive asks of its axis this cycle: follow the target (operation
// enabled, CSP), or stand where it is (the brake).
struct AxisDemand {
  bool follow = false;
  std::int32_t target = 0;           // 607Ah, counts
  std::int32_t velocity_offset = 0;  // 60B1h, counts/s
};

// Where the axis stands, and an error it raises itself (603Fh; 0: none),
// e.g. its position feedback lost.
struct AxisReading {
  double position = 0.0;  // counts
  double velocity = 0.0;  // counts/s
  std::uint16_t error_code = 0;
};

// One axis that follows its target at a bounded speed and stands otherwise.
class BoundedSpeedAxis {
 public:
  BoundedSpeedAxis(double max_speed_counts_s, double position);
  AxisReading Step(double dt_s, const AxisDemand& demand);

 private:
  double max_speed_counts_s_;
  double position_;
};

class CspAxes {
 public:
  virtual ~CspAxes() = default;
  // One drive cycle of `dt_s`. `command_utime` is when the master's latest
  // write arrived: the instant its targets are for (a Modbus write carries
  // no time of its own).
  virtual void Step(double dt_s, std::int64_t command_utime, const std::array<AxisDemand, kCabinetDrives>& demands) = 0;
  virtual AxisReading Reading(int drive) const = 0;
};

// Six bounded-speed axes, all starting at `position`.
class SimulatedAxes final : public CspAxes {
 public:
  SimulatedAxes(double max_speed_counts_s, double position);
  void Step(double dt_s, std::int64_t command_utime, const std::array<AxisDemand, kCabinetDrives>& demands) override;
  AxisReading Reading(int drive) const override { return readings_[static_cast<std::size_t>(drive)]; }

 private:
  std::array<BoundedSpeedAxis, kCabinetDrives> axes_;
  std::array<AxisReading, kCabinetDrives> readings_{};
};

}  // namespace edsp::cia402
