#pragma once
// Command-line options every node process takes, and what they build:
//   --config FILE      platform config (TOML), default config/huang2021.toml
//   --group FILE       deploy group file; its [transport] section routes channels
//   --session-id N     launch session; commands of other sessions are refused
//   --member NAME      this process's [[member]] name in the group file (edsp-launch
//                      passes it): in a group spanning hosts it decides which
//                      channels this process reads from shared memory
//   --lcm-url URL      overrides the group file's LCM URL

#include <cstdint>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "edsp/transport/transport_config.h"

namespace edsp {

struct NodeOptions {
  std::string config_path = "config/huang2021.toml";
  std::string group_path;
  std::int64_t session_id = 1;
  std::string member;
  std::string lcm_url;
};

void AddNodeOptions(CLI::App* app, NodeOptions* options);

// A node process's command line: its description, the options every node
// takes (in `node` once parsed), and room for its own with add_option.
class NodeApp : public CLI::App {
 public:
  explicit NodeApp(std::string description) : CLI::App(std::move(description)) { AddNodeOptions(this, &node); }
  NodeOptions node;
};

// The transport config from the group file (defaults without one; read by
// its one parser, group_file.h), routed for this member (host_routes.h), with
// the --lcm-url override applied. Throws std::runtime_error naming the file,
// line and key.
TransportConfig TransportFor(const NodeOptions& options);

// Reads a whole file; throws std::runtime_error naming it.
std::string ReadTextFile(const std::string& path);

}  // namespace edsp
