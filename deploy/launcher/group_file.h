#pragma once
// A process-group file (TOML): which programs form the group, in start
// order, with their arguments, environment, host and restart policy. The
// same file's [transport] section routes the group's channels.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

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

  // The distinct hosts of the members, sorted; more than one: LCM crosses machines.
  std::vector<std::string> MemberHosts() const;
};

// Throws std::runtime_error naming the file, line and key. The [transport]
// section is checked too (a group spanning hosts needs ttl ≥ 1, a writer per
// shared-memory channel and a fixed session id: every host's launcher must
// agree on it). Member args may
// use ${NAME} and ${NAME:-default}, expanded from the launcher's environment
// (e.g. `deploy/edsp demo` sets the PR mode and log directory per run); an
// unset NAME without a default is an error.
GroupSpec LoadGroupFile(const std::string& path);

// The expansion above. `lookup` returns nullptr for an unset variable.
// Throws std::invalid_argument naming the variable or the malformed text.
std::string ExpandVariables(const std::string& text, const std::function<const char*(const std::string&)>& lookup);

}  // namespace edsp
