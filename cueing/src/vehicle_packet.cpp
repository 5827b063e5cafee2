#include "edsp/cueing/vehicle_packet.h"

#include <cmath>
#include <cstring>

#include <fmt/format.h>

namespace edsp {
namespace {

constexpr std::uint32_t kMagic = 0x56534445;  // "EDSV" read little-endian
constexpr std::uint16_t kVersion = 1;
constexpr std::uint32_t kAngularAccelerationFlag = 1;
constexpr double kMaxSpecificForce_m_s2 = 5.0 * kStandardGravity_m_s2;
constexpr double kMaxAngularVelocity_rad_s = kTwoPi;
constexpr double kMaxAngularAcceleration_rad_s2 = 50.0;

// Little-endian reads and writes whatever the host's order.
template <typename Unsigned>
Unsigned ReadUnsigned(const std::uint8_t* p) {
  Unsigned value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) value |= static_cast<Unsigned>(Unsigned{p[i]} << (8 * i));
  return value;
}

template <typename Unsigned>
void WriteUnsigned(std::uint8_t* p, Unsigned value) {
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) p[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

float ReadFloat(const std::uint8_t* p) {
  const std::uint32_t bits = ReadUnsigned<std::uint32_t>(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

double ReadDouble(const std::uint8_t* p) {
  const std::uint64_t bits = ReadUnsigned<std::uint64_t>(p);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

void WriteFloat(std::uint8_t* p, double value) {
  const auto single = static_cast<float>(value);
  std::uint32_t bits;
  std::memcpy(&bits, &single, sizeof bits);
  WriteUnsigned(p, bits);
}

void WriteDouble(std::uint8_t* p, double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  WriteUnsigned(p, bits);
}

// Three float32 at `p` as a vector.
Vector3 ReadVector(const std::uint8_t* p) {
  Vector3 v;
  for (int axis = 0; axis < 3; ++axis) v(axis) = static_cast<double>(ReadFloat(p + 4 * axis));
  return v;
}

// Why `v` is no vector of `field` (an axis not finite or beyond `limit`), naming the axis.
std::optional<std::string> VectorError(const Vector3& v, const char* field, double limit, const char* unit) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(v(axis)) || std::fabs(v(axis)) > limit) {
      return fmt::format("{} {} = {} {}: must be finite and within ±{:.4g}", field, "xyz"[axis], v(axis), unit, limit);
    }
  }
  return std::nullopt;
}

ParsedVehiclePacket Refused(std::string error) { return {std::nullopt, std::move(error)}; }

}  // namespace

const char* CueCommandName(CueCommand command) {
  switch (command) {
    case CueCommand::kEngage: return "engage";
    case CueCommand::kDisengage: return "disengage";
    case CueCommand::kFreeze: return "freeze";
    case CueCommand::kEStop: return "e-stop";
  }
  return "?";
}

std::optional<CueCommand> CueCommandFromNumber(int value) {
  if (value < static_cast<int>(CueCommand::kEngage) || value > static_cast<int>(CueCommand::kEStop))
    return std::nullopt;
  return static_cast<CueCommand>(value);
}

std::optional<std::string> VehicleNumbersError(const VehiclePacket& packet) {
  if (!std::isfinite(packet.time_s)) return fmt::format("time_s = {}: must be finite", packet.time_s);
  if (auto error = VectorError(packet.specific_force_m_s2, "specific force", kMaxSpecificForce_m_s2, "m/s²")) {
    return error;
  }
  if (auto error = VectorError(packet.angular_velocity_rad_s, "angular velocity", kMaxAngularVelocity_rad_s, "rad/s")) {
    return error;
  }
  if (packet.angular_acceleration_rad_s2) {
    return VectorError(*packet.angular_acceleration_rad_s2, "angular acceleration", kMaxAngularAcceleration_rad_s2,
                       "rad/s²");
  }
  return std::nullopt;
}

ParsedVehiclePacket ParseVehiclePacket(const std::uint8_t* data, std::size_t size) {
  if (size != kVehiclePacketBytes) {
    return Refused(fmt::format("a vehicle packet is {} bytes, this one {}", kVehiclePacketBytes, size));
  }
  if (const auto magic = ReadUnsigned<std::uint32_t>(data); magic != kMagic) {
    return Refused(fmt::format("magic 0x{:08x} is not \"EDSV\" (0x{:08x})", magic, kMagic));
  }
  if (const auto version = ReadUnsigned<std::uint16_t>(data + 4); version != kVersion) {
    return Refused(fmt::format("version {} (this edsp reads version {})", version, kVersion));
  }
  const auto command = CueCommandFromNumber(ReadUnsigned<std::uint16_t>(data + 6));
  if (!command) {
    return Refused(fmt::format("command {}: must be {}", ReadUnsigned<std::uint16_t>(data + 6), kCueCommandsText));
  }
  const auto flags = ReadUnsigned<std::uint32_t>(data + 12);
  if ((flags & ~kAngularAccelerationFlag) != 0)
    return Refused(fmt::format("flags 0x{:x}: only bit 0 is defined", flags));
  VehiclePacket packet;
  packet.command = *command;
  packet.sequence = ReadUnsigned<std::uint32_t>(data + 8);
  packet.time_s = ReadDouble(data + 16);
  packet.specific_force_m_s2 = ReadVector(data + 24);
  packet.angular_velocity_rad_s = ReadVector(data + 36);
  if ((flags & kAngularAccelerationFlag) != 0) packet.angular_acceleration_rad_s2 = ReadVector(data + 48);
  if (auto error = VehicleNumbersError(packet)) return Refused(std::move(*error));
  return {packet, ""};
}

std::array<std::uint8_t, kVehiclePacketBytes> EncodeVehiclePacket(const VehiclePacket& packet) {
  std::array<std::uint8_t, kVehiclePacketBytes> bytes{};
  std::uint8_t* p = bytes.data();
  WriteUnsigned(p, kMagic);
  WriteUnsigned(p + 4, kVersion);
  WriteUnsigned(p + 6, static_cast<std::uint16_t>(packet.command));
  WriteUnsigned(p + 8, packet.sequence);
  WriteUnsigned(p + 12, packet.angular_acceleration_rad_s2 ? kAngularAccelerationFlag : 0u);
  WriteDouble(p + 16, packet.time_s);
  for (int axis = 0; axis < 3; ++axis) {
    WriteFloat(p + 24 + 4 * axis, packet.specific_force_m_s2(axis));
    WriteFloat(p + 36 + 4 * axis, packet.angular_velocity_rad_s(axis));
    if (packet.angular_acceleration_rad_s2) WriteFloat(p + 48 + 4 * axis, (*packet.angular_acceleration_rad_s2)(axis));
  }
  return bytes;
}

}  // namespace edsp
