#include "edsp/node/group_file.h"

#include <algorithm>
#include <cctype>
#include <sched.h>

#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "edsp/transport/transport_section.h"

namespace edsp {

namespace {

std::vector<std::string> ReadArgs(const ConfigSection& member, const VariableLookup& variables) {
  std::vector<std::string> args = member.Strings("args");
  if (!variables) return args;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      args[i] = ExpandVariables(args[i], variables);
    } catch (const std::invalid_argument& e) {
      member.FailAtElement("args", i, fmt::format("{} args: {}", member.label(), e.what()));
    }
  }
  return args;
}

RestartPolicy ReadRestart(const ConfigSection& member, RestartPolicy fallback) {
  if (!member.Has("restart")) return fallback;
  const std::string r = member.String("restart", "");
  if (r == "never") return RestartPolicy::kNever;
  if (r == "on-failure") return RestartPolicy::kOnFailure;
  if (r == "always") return RestartPolicy::kAlways;
  member.Fail("restart", fmt::format("{} restart = \"{}\" must be never, on-failure or always", member.label(), r));
}

std::map<std::string, std::string> ReadEnv(const ConfigSection& member) {
  std::map<std::string, std::string> env;
  const ConfigSection table = member.Table("env");
  for (const std::string& name : table.Keys()) env[name] = table.String(name, "");
  return env;
}

MemberSpec ReadMember(const ConfigSection& member, const VariableLookup& variables) {
  member.RejectUnknownKeys({"name", "command", "args", "env", "host", "restart", "max_restarts", "start_delay_ms",
                            "realtime_priority", "cpus", "requires", "node_options", "enabled"});
  MemberSpec m;
  m.name = member.String("name", "");
  m.command = member.String("command", "");
  m.args = ReadArgs(member, variables);
  m.env = ReadEnv(member);
  m.host = member.String("host", m.host);
  m.restart = ReadRestart(member, m.restart);
  m.max_restarts = static_cast<int>(member.Integer("max_restarts", m.max_restarts, 0, 100000));
  m.start_delay_ms = static_cast<int>(member.Integer("start_delay_ms", m.start_delay_ms, 0, 100000));
  // 0: not real-time.
  m.realtime_priority = static_cast<int>(member.Integer("realtime_priority", m.realtime_priority, 0, 99));
  for (const std::int64_t cpu : member.Integers("cpus", 0, CPU_SETSIZE - 1)) m.cpus.push_back(static_cast<int>(cpu));
  m.requires_members = member.Strings("requires");
  m.node_options = member.Bool("node_options", m.node_options);
  if (m.name.empty() || m.command.empty()) {
    member.Fail("", fmt::format("{} needs a name and a command", member.label()));
  }
  return m;
}

void ReadGroupSection(const ConfigFile& file, GroupSpec* group) {
  const ConfigSection g = file.Section("group");
  g.RejectUnknownKeys({"name", "config", "session_id"});
  group->name = g.String("name", group->name);
  group->config = g.String("config", group->config);
  group->session_id = g.Integer("session_id", group->session_id);
  if (group->session_id < 0) g.Fail("session_id", "[group] session_id must be a non-negative integer");
}

std::vector<MemberSpec> ReadMembers(const ConfigFile& file, const VariableLookup& variables) {
  std::vector<MemberSpec> out;
  std::set<std::string> names;
  // No [[member]]: a file of routes only, which the launcher refuses (LoadGroupFile).
  for (const ConfigSection& member : file.Root().TableArray("member")) {
    out.push_back(ReadMember(member, variables));
    if (!names.insert(out.back().name).second) {
      member.Fail("name", fmt::format("two members named \"{}\"", out.back().name));
    }
    // Checked as any member, then left out: `enabled = false` is a shipped
    // member one line away from running (edsp-web in the sim groups).
    if (!member.Bool("enabled", true)) out.pop_back();
  }
  return out;
}

std::map<std::string, HostSpec> ReadHosts(const ConfigFile& file) {
  std::map<std::string, HostSpec> hosts;
  for (const auto& [name, table] : file.Section("hosts").Tables()) {
    table.RejectUnknownKeys({"interface"});
    hosts[name].interface = table.String("interface", "");
  }
  return hosts;
}

// What only makes sense once every member is read.
void CheckMembers(const GroupSpec& group) {
  std::map<std::string, std::string> host_of;
  for (const MemberSpec& m : group.members) host_of[m.name] = m.host;
  for (const MemberSpec& m : group.members) {
    for (const std::string& r : m.requires_members) {
      if (!host_of.count(r))
        throw ConfigError(fmt::format("{}: member {} requires \"{}\", which is no member", group.path, m.name, r));
      if (host_of[r] != m.host) {
        throw ConfigError(
            fmt::format("{}: member {} (host {}) requires {} on host {}: systemd orders units of one host only",
                        group.path, m.name, m.host, r, host_of[r]));
      }
    }
    if (!group.hosts.empty() && !group.hosts.count(m.host)) {
      throw ConfigError(
          fmt::format("{}: member {} is on host {}, which [hosts] does not list", group.path, m.name, m.host));
    }
  }
  const std::vector<std::string> hosts = group.MemberHosts();
  if (hosts.size() > 1 && group.session_id == 0) {
    throw ConfigError(
        fmt::format("{}: the group spans hosts ({}): set [group] session_id so every host's launcher "
                    "gives its members the same session (commands of other sessions are refused)",
                    group.path, fmt::join(hosts, ", ")));
  }
}

// What transport needs of the members: which host each runs on.
HostAssignment HostsOf(const std::vector<MemberSpec>& members) {
  HostAssignment hosts;
  for (const MemberSpec& m : members) hosts[m.name] = m.host;
  return hosts;
}

GroupSpec GroupOf(const ConfigFile& file, const VariableLookup& variables) {
  GroupSpec group;
  group.path = file.origin();
  ReadGroupSection(file, &group);
  group.members = ReadMembers(file, variables);
  if (group.name.empty()) group.name = group.path;
  group.hosts = ReadHosts(file);
  CheckMembers(group);
  group.transport = ReadTransportSection(file, HostsOf(group.members));
  return group;
}

}  // namespace

std::vector<std::string> GroupSpec::MemberHosts() const {
  std::set<std::string> distinct;
  for (const MemberSpec& m : members) distinct.insert(m.host);
  return {distinct.begin(), distinct.end()};
}

std::string ExpandVariables(const std::string& text, const VariableLookup& lookup) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '$' || i + 1 >= text.size() || text[i + 1] != '{') {
      out += text[i];
      continue;
    }
    const std::size_t close = text.find('}', i + 2);
    if (close == std::string::npos) throw std::invalid_argument("unclosed ${ in \"" + text + "\"");
    const std::string body = text.substr(i + 2, close - i - 2);
    const std::size_t dash = body.find(":-");
    const std::string name = body.substr(0, dash);
    const bool valid_name = !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) &&
                            std::all_of(name.begin(), name.end(),
                                        [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
    if (!valid_name) throw std::invalid_argument("bad variable name in \"" + text + "\"");
    const char* value = lookup(name);
    if (value != nullptr && *value != '\0') {
      out += value;
    } else if (dash != std::string::npos) {
      out += body.substr(dash + 2);
    } else {
      throw std::invalid_argument("${" + name + "} is not set and has no default (${" + name + ":-...})");
    }
    i = close;
  }
  return out;
}

GroupSpec ParseGroupFile(const std::string& toml_text, const std::string& origin, const VariableLookup& variables) {
  return GroupOf(ConfigFile::Parse(toml_text, origin), variables);
}

GroupSpec ReadGroupFile(const std::string& path, const VariableLookup& variables) {
  return ParseGroupFile(ConfigFile::ReadText(path), path, variables);
}

TransportConfig LoadTransportConfig(const std::string& path) { return ReadGroupFile(path).transport; }

}  // namespace edsp
