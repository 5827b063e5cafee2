#pragma once
// One drive's cyclic synchronous position (CSP) process image in the
// drive's own units (counts, counts/s), and the scaling between those and
// the motor angles the bridge computes in. The objects are CiA 402's
// (cia402.h); the same image travels over Modbus TCP (modbus_register_map.h)
// or an EtherCAT master's PDOs (docs/drives.md).

#include <cstdint>
#include <optional>
#include <string>

namespace edsp::cia402 {

// RxPDO: master → drive.
struct CspCommand {
  std::uint16_t controlword = 0;      // 6040h
  std::int8_t mode_of_operation = 0;  // 6060h (8 = CSP)
  std::int32_t target_position = 0;   // 607Ah, counts
  std::int32_t velocity_offset = 0;   // 60B1h, counts/s (feed-forward)
};

// TxPDO: drive → master.
struct CspFeedback {
  std::uint16_t statusword = 0;      // 6041h
  std::int8_t mode_display = 0;      // 6061h
  std::int32_t position_actual = 0;  // 6064h, counts
  std::int32_t velocity_actual = 0;  // 606Ch, counts/s
  std::uint16_t error_code = 0;      // 603Fh
  // edsp's: the drive cycle (mod 2^16) that latched this image. A request
  // reads what the drives' last cycle latched, before the commands it
  // carries took effect; a master that waits for a state it commanded
  // trusts only an image latched after its command (a new count).
  std::uint16_t cycle_count = 0;
};

// Motor angle (rad from the leg's home) ↔ drive counts:
// counts = offset + direction · counts_per_rad · angle.
struct DriveScaling {
  double counts_per_rad = 0.0;     // encoder counts per motor radian (> 0)
  std::int32_t offset_counts = 0;  // the drive's count at the leg's home
  int direction = 1;               // +1, or −1 for a motor mounted the other way

  // Nothing when usable, else what is wrong (for config errors naming the drive).
  std::optional<std::string> Problem() const;
  // The count of `angle_rad` (counts/s of `rate_rad_s`) before rounding:
  // where an axis stands, for a reading; never a target.
  double Counts(double angle_rad) const;
  double CountRate(double rate_rad_s) const;
  // The count for `angle_rad`; nullopt when it is not finite or does not
  // fit the drive's 32-bit position (never a wrapped target).
  std::optional<std::int32_t> ToCounts(double angle_rad) const;
  std::optional<std::int32_t> ToCountsPerSecond(double rate_rad_s) const;
  double ToAngle(std::int32_t counts) const;
  double ToRate(std::int32_t counts_per_s) const;
};

}  // namespace edsp::cia402
