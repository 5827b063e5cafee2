#pragma once
// Where a group spans hosts: shared memory joins members of one host only,
// LCM carries everything between hosts, and both are decided from the group
// file (never from which segments happen to be visible at run time).
//
// For a channel routed shm or both in such a group, with writer W on host H:
//   - W publishes on shared memory, and on LCM at full rate as well when any
//     reader (the listed readers, or else any member) is on another host;
//   - members on H read the shared memory;
//   - members on other hosts, and programs that are no member, read LCM.
// docs/multihost.md.

#include <string>
#include <vector>

#include "edsp/transport/transport_config.h"

namespace edsp {

// The distinct hosts of the group's members, sorted.
std::vector<std::string> GroupHosts(const TransportConfig& config);

// The LCM URL's ttl (LCM's own default is 0: the packets never leave the
// host). Throws TransportError if the ttl option is not an integer 0..255.
int LcmUrlTtl(const std::string& url);

// A group spanning hosts needs ttl ≥ 1, a writer (a known member) for every
// shm/both channel, and known readers. Throws TransportError naming `origin`,
// the channel and the key; a one-host group always passes.
void CheckHostRoutes(const TransportConfig& config, const std::string& origin);

// The routes as `member` uses them (the rules above). An empty or unknown
// member is a program outside the group: it reads and writes LCM only.
TransportConfig RoutesForMember(const TransportConfig& group, const std::string& member);

}  // namespace edsp
