#pragma once
// edsp-cueing live: the cueing source as a node of a running group.
//   edsp-cueing live --cueing FILE [--input udp|lcm] [--udp ADDRESS:PORT] [--config FILE] [--group FILE]
//                    [--session-id N]
// Binds the vehicle's UDP socket (default 127.0.0.1:7400; docs/cueing.md,
// "The packet"), or with --input lcm reads EDSP_VEHICLE, then at the
// stack's 1 kHz: the samples through the input guard
// and classical washout, EDSP_CUE_SETPOINT out, the planner asked to engage,
// disengage or stop as the host's command word says. Until SIGINT/SIGTERM.

#include <cstdint>
#include <string>

#include "edsp/node/node_options.h"

namespace edsp {

struct LiveOptions {
  NodeOptions node;
  std::string cueing_path;
  std::string input = "udp";           // or "lcm": EDSP_VEHICLE
  std::string udp = "127.0.0.1:7400";  // with input udp; "": no socket
};

int RunLive(const LiveOptions& options);

struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
// "127.0.0.1:7400", "[::1]:7400"; throws std::invalid_argument naming `option`.
HostPort ParseHostPort(const std::string& text, const std::string& option);

}  // namespace edsp
