#pragma once
// The UDP packet a vehicle model sends edsp-cueing (docs/cueing.md, "The
// packet"): 60 bytes, little-endian, one per vehicle sample.
//
//   offset  size  field
//        0     4  magic "EDSV"
//        4     2  version, 1
//        6     2  command: 1 engage, 2 disengage, 3 freeze, 4 e-stop (the
//                 state the host wants, sent in every packet: a lost packet
//                 loses no command)
//        8     4  sequence, +1 per packet (wraps)
//       12     4  flags: bit 0, angular acceleration present; others 0
//       16     8  time_s, float64: the vehicle's simulation time
//       24    12  specific force fx fy fz, float32, m/s², head frame {H}
//       36    12  angular velocity wx wy wz, float32, rad/s, {H}
//       48    12  angular acceleration, float32, rad/s², {H} (if flagged)
//
// Parsing checks everything a sender can get wrong and names it: size,
// magic, version, command, flags, and every number finite and within what
// any vehicle a rider survives makes (5 g, 2π rad/s, 50 rad/s²).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "edsp/cueing/vehicle_motion.h"

namespace edsp {

inline constexpr std::size_t kVehiclePacketBytes = 60;

enum class CueCommand : std::uint16_t { kEngage = 1, kDisengage = 2, kFreeze = 3, kEStop = 4 };
const char* CueCommandName(CueCommand command);
inline constexpr char kCueCommandsText[] = "1 engage, 2 disengage, 3 freeze or 4 e-stop";

struct VehiclePacket {
  CueCommand command = CueCommand::kEngage;
  std::uint32_t sequence = 0;
  double time_s = 0.0;
  Vector3 specific_force_m_s2 = Vector3(0.0, 0.0, kStandardGravity_m_s2);
  Vector3 angular_velocity_rad_s = Vector3::Zero();
  std::optional<Vector3> angular_acceleration_rad_s2;
};

struct ParsedVehiclePacket {
  std::optional<VehiclePacket> packet;
  std::string error;  // why not, naming the field and value
};

ParsedVehiclePacket ParseVehiclePacket(const std::uint8_t* data, std::size_t size);

// The command numbered `value` (1 engage … 4 e-stop), or nothing.
std::optional<CueCommand> CueCommandFromNumber(int value);
// Why `packet`'s numbers are no vehicle's (time not finite; a vector's axis
// not finite or beyond the limits above), naming the field, axis and value;
// nothing if they are. Every input's samples pass it: the UDP packet's and
// EDSP_VEHICLE's.
std::optional<std::string> VehicleNumbersError(const VehiclePacket& packet);

// Whether `sequence` comes after `latest` in a stream: ahead by less than
// half the sequence space, so newer across a wrap too (a repeat is not).
inline bool SequenceIsAhead(std::uint32_t sequence, std::uint32_t latest) {
  const std::uint32_t ahead = sequence - latest;
  return ahead != 0 && ahead < 0x80000000u;
}

// A packet's sequence as a cue's and a cueing setpoint's `segment` carry it
// (its low 31 bits): which vehicle sample a setpoint comes from, so that a
// log traces each sample to the drives (edsp-cueing delay).
inline std::int32_t VehicleSequenceAsSegment(std::uint32_t sequence) {
  return static_cast<std::int32_t>(sequence & 0x7fffffffU);
}
// The bytes of `packet` (float64 time, float32 vectors).
std::array<std::uint8_t, kVehiclePacketBytes> EncodeVehiclePacket(const VehiclePacket& packet);

}  // namespace edsp
