#pragma once
// How the group file's one parser (edsp/node/group_file.h) hands transport
// its section: the file already parsed as TOML, and the members' hosts it
// read from [[member]]. Transport reads [transport] from it and nothing else,
// so the file is read once and each part of it in one place. Includes
// toml++: for that parser, not for users of the bus.

#include <string>

#include <toml++/toml.h>

#include "edsp/transport/transport_config.h"

namespace edsp {

// The routes of `file`'s [transport] section (absent: the defaults) for
// members on `member_hosts`, checked as ParseTransportConfig checks them.
// Throws TransportError naming `origin`, the line and the key.
TransportConfig ReadTransportSection(const toml::table& file, const std::string& origin,
                                     const HostAssignment& member_hosts);

}  // namespace edsp
