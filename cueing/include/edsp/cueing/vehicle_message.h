#pragma once
// EDSP_VEHICLE's messages (vehicle_motion_t, docs/interfaces.md): a vehicle
// model's samples on the bus, the typed twin of the UDP packet. Read into
// the same VehiclePacket, through the same checks (VehicleNumbersError),
// so the cueing cannot tell which input a sample came by.

#include <cstdint>

#include "edsp/cueing/vehicle_packet.h"
#include "edsp/vehicle_motion_t.hpp"

namespace edsp {

// The sample `message` carries, or why not, naming the field and value (a
// command outside 1…4, a seq outside 0…2³²−1, the packet's checks). Its
// session is the reader's to check.
ParsedVehiclePacket ReadVehicleMessage(const vehicle_motion_t& message);

// `packet` as a message for `session_id` sent at `utime` (µs).
vehicle_motion_t VehicleMessage(const VehiclePacket& packet, std::int64_t session_id, std::int64_t utime);

}  // namespace edsp
