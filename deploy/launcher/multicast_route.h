#pragma once
// Which network interface this machine's kernel sends a multicast group's
// packets through: LCM 1.3 has no interface option, so the route for
// 224.0.0.0/4 decides, and a rig host with two networks (plant and office)
// must be checked before its members start talking on the wrong one.

#include <string>

#include "group_file.h"

namespace edsp {

// "239.255.76.67" from "udpm://239.255.76.67:7667?ttl=1"; empty for other providers.
std::string MulticastAddress(const std::string& lcm_url);

// The interface the route to `group_address` leaves by ("" if no route:
// the error says so). Throws std::runtime_error on a malformed address.
std::string MulticastRouteInterface(const std::string& group_address, std::string* error);

// A host whose [hosts.NAME] names an interface: the group's multicast must
// leave by it, or the members would talk on the wrong network (or none).
// Throws std::runtime_error naming the file, the host, the interface and
// the route found, with the command that adds the right one.
void CheckMulticastInterface(const GroupSpec& group, const std::string& host);

}  // namespace edsp
