#pragma once
// How the group file's one parser (edsp/node/group_file.h) hands transport
// its section: the file already parsed, and the members' hosts it read from
// [[member]]. Transport reads [transport] from it and nothing else, so the
// file is read once and each part of it in one place.

#include <string>

#include "edsp/config_file/config_file.h"

#include "edsp/transport/transport_config.h"

namespace edsp {

// The routes of `file`'s [transport] section (absent: the defaults) for
// members on `member_hosts`, checked as ParseTransportConfig checks them.
// Throws ConfigError naming the file, the line and the key.
TransportConfig ReadTransportSection(const ConfigFile& file, const HostAssignment& member_hosts);

}  // namespace edsp
