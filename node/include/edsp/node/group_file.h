#pragma once
// A process-group file (TOML), read here and nowhere else: which programs
// form the group ([[member]], in start order: arguments, environment, host,
// restart policy), its machines ([hosts.NAME]), its name, config and session
// ([group]), and the routes of its channels ([transport]), which transport
// reads from the parsed file given the members' hosts
// (edsp/transport/transport_section.h). edsp-launch starts the group from it
// (deploy/launcher/group_file.h); each member, edsp-ctl and the Python client
// take their routes from it (LoadTransportConfig).

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "edsp/transport/transport_config.h"

namespace edsp {

enum class RestartPolicy { kNever, kOnFailure, kAlways };

struct MemberSpec {
  std::string name;
  std::string command;  // a program in --bin-dir, or a path
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  std::string host = "local";
  RestartPolicy restart = RestartPolicy::kOnFailure;
  int max_restarts = 10;
  int start_delay_ms = 0;                     // pause after starting it, before the next
  bool node_options = true;                   // pass --config, --group, --session-id
  int realtime_priority = 0;                  // 1..99: SCHED_FIFO at this priority; 0: normal
  std::vector<int> cpus;                      // CPU affinity; empty: any CPU
  std::vector<std::string> requires_members;  // systemd Requires= (members of the same host)
};

// A machine of a group spanning hosts ([hosts.NAME]).
struct HostSpec {
  std::string interface;  // where the LCM multicast must leave (checked at launch)
};

struct GroupSpec {
  std::string path;
  std::string name;
  std::string config = "config/huang2021.toml";
  std::int64_t session_id = 0;  // 0: a fresh one per launch
  std::vector<MemberSpec> members;
  std::map<std::string, HostSpec> hosts;
  TransportConfig transport;  // [transport], routed for the members' hosts

  // The distinct hosts of the members, sorted; more than one: LCM crosses machines.
  std::vector<std::string> MemberHosts() const;
};

// The value of the variable NAME of ${NAME} in member args; nullptr if unset.
using VariableLookup = std::function<const char*(const std::string&)>;

// Reads the group file at `path`. Throws ConfigError naming the file,
// line and key (TransportError for routes the hosts cannot carry). Checked as well: a group
// spanning hosts needs ttl ≥ 1, a writer per shared-memory channel and a
// fixed session id (every host's launcher must agree on it).
//
// Given `variables`, member args may use ${NAME} and ${NAME:-default},
// expanded from them; an unset NAME without a default is an error. Without,
// args are kept as written: a reader that wants the routes only (a member,
// edsp-ctl) does not have the launcher's environment and needs no args.
GroupSpec ReadGroupFile(const std::string& path, const VariableLookup& variables = nullptr);
// The same from TOML text; `origin` names it in errors.
GroupSpec ParseGroupFile(const std::string& toml_text, const std::string& origin,
                         const VariableLookup& variables = nullptr);

// The group file's routes: ReadGroupFile(path).transport.
TransportConfig LoadTransportConfig(const std::string& path);

// The expansion above. `lookup` returns nullptr for an unset variable.
// Throws std::invalid_argument naming the variable or the malformed text.
std::string ExpandVariables(const std::string& text, const VariableLookup& lookup);

}  // namespace edsp
