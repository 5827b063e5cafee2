#include "edsp/cueing/vehicle_message.h"

#include <limits>
#include <string>
#include <utility>

#include <fmt/format.h>

namespace edsp {
namespace {

Vector3 ToVector(const double (&v)[3]) { return Vector3(v[0], v[1], v[2]); }

void FromVector(const Vector3& v, double (&out)[3]) {
  for (int axis = 0; axis < 3; ++axis) out[axis] = v(axis);
}

ParsedVehiclePacket Refused(std::string error) { return {std::nullopt, std::move(error)}; }

}  // namespace

ParsedVehiclePacket ReadVehicleMessage(const vehicle_motion_t& message) {
  const auto command = CueCommandFromNumber(message.command);
  if (!command) return Refused(fmt::format("command {}: must be {}", message.command, kCueCommandsText));
  if (message.seq < 0 || message.seq > std::numeric_limits<std::uint32_t>::max()) {
    return Refused(fmt::format("seq {}: must be 0…{} (it wraps to 0 there)", message.seq,
                               std::numeric_limits<std::uint32_t>::max()));
  }
  VehiclePacket packet;
  packet.command = *command;
  packet.sequence = static_cast<std::uint32_t>(message.seq);
  packet.time_s = message.time_s;
  packet.specific_force_m_s2 = ToVector(message.specific_force);
  packet.angular_velocity_rad_s = ToVector(message.angular_velocity);
  if (message.has_angular_acceleration) packet.angular_acceleration_rad_s2 = ToVector(message.angular_acceleration);
  if (auto error = VehicleNumbersError(packet)) return Refused(std::move(*error));
  return {packet, ""};
}

vehicle_motion_t VehicleMessage(const VehiclePacket& packet, std::int64_t session_id, std::int64_t utime) {
  vehicle_motion_t message{};
  message.utime = utime;
  message.seq = packet.sequence;
  message.session_id = session_id;
  message.command = static_cast<std::int8_t>(packet.command);
  message.time_s = packet.time_s;
  FromVector(packet.specific_force_m_s2, message.specific_force);
  FromVector(packet.angular_velocity_rad_s, message.angular_velocity);
  message.has_angular_acceleration = packet.angular_acceleration_rad_s2.has_value();
  if (packet.angular_acceleration_rad_s2) FromVector(*packet.angular_acceleration_rad_s2, message.angular_acceleration);
  return message;
}

}  // namespace edsp
