#pragma once
// Which path each channel takes, read from the deploy group file's
// [transport] section (never decided in code). docs/transport.md.
//
//   [transport]
//   lcm_url = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"
//   shm_prefix = "edsp"          # segment names: <prefix>.<channel>
//   shm_permissions = "0600"
//   [transport.channels.EDSP_LEG_COMMAND]
//   path = "both"                # lcm | shm | both
//   mirror_every = 10            # both: every 10th message also on LCM
//   slots = 64
//   slot_size_bytes = 1024
//   writer = "kinematics"        # a group spanning hosts: the member that publishes it
//   readers = ["actuator_bridge"] # optional: who reads it (default: anyone)
// Which members share a host (shared memory only ever joins members of one
// host: host_routes.h) transport is told, as a HostAssignment: it reads no
// [[member]] itself. The group file's one parser (edsp/node/group_file.h)
// reads the members and hands their hosts over with the parsed [transport]
// section (transport_section.h).

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "edsp/transport/lcm_transport.h"

namespace edsp {

enum class ChannelPath { kLcm, kShm, kBoth };
const char* ChannelPathName(ChannelPath path);

struct ChannelRoute {
  ChannelPath path = ChannelPath::kLcm;
  std::uint32_t mirror_every = 1;        // LCM mirror decimation for kBoth
  std::uint32_t slots = 64;              // shared-memory ring length (power of two)
  std::uint32_t slot_size_bytes = 4096;  // largest encoded message
  std::string writer;                    // the publishing member (multi-host groups)
  std::vector<std::string> readers;      // empty: any member may read it
};

// Each member's host: member name → host ("local" unless the group says).
using HostAssignment = std::map<std::string, std::string>;

struct TransportConfig {
  std::string lcm_url = kDefaultLcmUrl;
  std::string shm_prefix = "edsp";
  mode_t shm_permissions = 0600;
  std::map<std::string, ChannelRoute> channels;  // channels not listed use LCM
  HostAssignment member_hosts;                   // as the group's parser gave them

  const ChannelRoute& Route(const std::string& channel) const;
  std::string SegmentName(const std::string& channel) const;
};

// Parses the [transport] section of TOML text (absent section: defaults) for
// members on `member_hosts`, then checks a group that spans hosts
// (CheckHostRoutes). Throws ConfigError naming `origin`, the line and the
// key (TransportError for routes the hosts cannot carry). A group file's routes, its members' hosts included, come from
// LoadTransportConfig (edsp/node/group_file.h).
TransportConfig ParseTransportConfig(const std::string& toml_text, const std::string& origin,
                                     const HostAssignment& member_hosts);

}  // namespace edsp
