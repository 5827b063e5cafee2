// libFuzzer: the UDP packet a vehicle model sends edsp-cueing, before
// anything is trusted. Each either parses or is refused with a reason; a
// parsed packet encodes and parses back to itself, and the input guard
// fed with it never yields a sample that is not finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "edsp/cueing/vehicle_input.h"
#include "edsp/cueing/vehicle_packet.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const edsp::ParsedVehiclePacket parsed = edsp::ParseVehiclePacket(data, size);
  if (!parsed.packet) {
    if (parsed.error.empty()) std::abort();  // a refusal always says why
    return 0;
  }
  const auto again = edsp::EncodeVehiclePacket(*parsed.packet);
  const edsp::ParsedVehiclePacket reparsed = edsp::ParseVehiclePacket(again.data(), again.size());
  if (!reparsed.packet || reparsed.packet->command != parsed.packet->command ||
      reparsed.packet->angular_acceleration_rad_s2 != parsed.packet->angular_acceleration_rad_s2 ||
      reparsed.packet->sequence != parsed.packet->sequence || reparsed.packet->time_s != parsed.packet->time_s ||
      reparsed.packet->specific_force_m_s2 != parsed.packet->specific_force_m_s2 ||
      reparsed.packet->angular_velocity_rad_s != parsed.packet->angular_velocity_rad_s) {
    std::abort();
  }
  edsp::VehicleInput input(edsp::VehicleInputParameters{});
  (void)input.Accept(*parsed.packet, 0.0);
  for (double t : {0.0, 0.05, 0.5, 2.0}) {
    const edsp::VehicleSample sample = input.At(t);
    if (!sample.specific_force_m_s2.allFinite() || !sample.angular_velocity_rad_s.allFinite()) std::abort();
  }
  return 0;
}
