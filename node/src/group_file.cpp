#include "edsp/node/group_file.h"

#include <algorithm>
#include <cctype>
#include <sched.h>

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "edsp/transport/transport_section.h"

namespace edsp {

namespace {

[[noreturn]] void Fail(const std::string& path, const toml::node& node, const std::string& what) {
  throw std::runtime_error(fmt::format("{}:{}: {}", path, node.source().begin.line, what));
}

std::string RequireString(const std::string& path, const toml::node& node, const std::string& key) {
  if (!node.is_string()) Fail(path, node, key + " must be a string");
  return *node.value<std::string>();
}

std::vector<std::string> ReadArgs(const std::string& path, const toml::node& node, const std::string& where,
                                  const VariableLookup& variables) {
  const toml::array* args = node.as_array();
  if (args == nullptr) Fail(path, node, where + " args must be an array of strings");
  std::vector<std::string> out;
  for (const toml::node& a : *args) {
    const std::string text = RequireString(path, a, where + " args");
    if (!variables) {
      out.push_back(text);
      continue;
    }
    try {
      out.push_back(ExpandVariables(text, variables));
    } catch (const std::invalid_argument& e) {
      Fail(path, a, fmt::format("{} args: {}", where, e.what()));
    }
  }
  return out;
}

MemberSpec ReadMember(const std::string& path, const toml::table& t, int index, const VariableLookup& variables) {
  MemberSpec m;
  const std::string where = fmt::format("[[member]] #{}", index + 1);
  for (auto&& [key, node] : t) {
    const std::string k(key.str());
    if (k == "name") {
      m.name = RequireString(path, node, where + " name");
    } else if (k == "command") {
      m.command = RequireString(path, node, where + " command");
    } else if (k == "args") {
      m.args = ReadArgs(path, node, where, variables);
    } else if (k == "env") {
      const toml::table* env = node.as_table();
      if (env == nullptr) Fail(path, node, where + " env must be a table");
      for (auto&& [name, value] : *env) m.env[std::string(name.str())] = RequireString(path, value, "env");
    } else if (k == "host") {
      m.host = RequireString(path, node, where + " host");
    } else if (k == "restart") {
      const std::string r = RequireString(path, node, where + " restart");
      if (r == "never")
        m.restart = RestartPolicy::kNever;
      else if (r == "on-failure")
        m.restart = RestartPolicy::kOnFailure;
      else if (r == "always")
        m.restart = RestartPolicy::kAlways;
      else
        Fail(path, node, fmt::format("{} restart = \"{}\" must be never, on-failure or always", where, r));
    } else if (k == "max_restarts" || k == "start_delay_ms") {
      const auto v = node.value<std::int64_t>();
      if (!node.is_integer() || *v < 0 || *v > 100000)
        Fail(path, node, where + " " + k + " must be an integer 0..100000");
      (k == "max_restarts" ? m.max_restarts : m.start_delay_ms) = static_cast<int>(*v);
    } else if (k == "realtime_priority") {
      const auto v = node.value<std::int64_t>();
      if (!node.is_integer() || *v < 0 || *v > 99)
        Fail(path, node, where + " realtime_priority must be an integer 0..99 (0: not real-time)");
      m.realtime_priority = static_cast<int>(*v);
    } else if (k == "cpus") {
      const toml::array* cpus = node.as_array();
      if (cpus == nullptr) Fail(path, node, where + " cpus must be an array of CPU numbers");
      for (const toml::node& c : *cpus) {
        const auto v = c.value<std::int64_t>();
        if (!c.is_integer() || *v < 0 || *v >= CPU_SETSIZE)
          Fail(path, c, where + " cpus: each must be a CPU number 0..1023");
        m.cpus.push_back(static_cast<int>(*v));
      }
    } else if (k == "requires") {
      const toml::array* list = node.as_array();
      if (list == nullptr) Fail(path, node, where + " requires must be an array of member names");
      for (const toml::node& r : *list) m.requires_members.push_back(RequireString(path, r, where + " requires"));
    } else if (k == "node_options") {
      if (!node.is_boolean()) Fail(path, node, where + " node_options must be true or false");
      m.node_options = *node.value<bool>();
    } else {
      Fail(path, node, fmt::format("unknown key {} {}", where, k));
    }
  }
  if (m.name.empty() || m.command.empty()) {
    throw std::runtime_error(fmt::format("{}: {} needs a name and a command", path, where));
  }
  return m;
}

void ReadGroupSection(const std::string& path, const toml::table& root, GroupSpec* group) {
  const toml::table* g = root["group"].as_table();
  if (g == nullptr) return;
  for (auto&& [key, node] : *g) {
    const std::string k(key.str());
    if (k == "name")
      group->name = RequireString(path, node, "[group] name");
    else if (k == "config")
      group->config = RequireString(path, node, "[group] config");
    else if (k == "session_id") {
      if (!node.is_integer() || *node.value<std::int64_t>() < 0)
        Fail(path, node, "[group] session_id must be a non-negative integer");
      group->session_id = *node.value<std::int64_t>();
    } else {
      Fail(path, node, "unknown key [group] " + k);
    }
  }
}

std::vector<MemberSpec> ReadMembers(const std::string& path, const toml::table& root, const VariableLookup& variables) {
  const toml::array* members = root["member"].as_array();
  std::vector<MemberSpec> out;
  if (members == nullptr) return out;  // a file of routes only: the launcher refuses it (LoadGroupFile)
  std::set<std::string> names;
  for (std::size_t i = 0; i < members->size(); ++i) {
    const toml::table* t = (*members)[i].as_table();
    if (t == nullptr) Fail(path, (*members)[i], "[[member]] must be a table");
    out.push_back(ReadMember(path, *t, static_cast<int>(i), variables));
    if (!names.insert(out.back().name).second) {
      throw std::runtime_error(fmt::format("{}: two members named \"{}\"", path, out.back().name));
    }
  }
  return out;
}

std::map<std::string, HostSpec> ReadHosts(const std::string& path, const toml::table& root) {
  std::map<std::string, HostSpec> hosts;
  const toml::node* section = root.get("hosts");
  if (section == nullptr) return hosts;
  const toml::table* table = section->as_table();
  if (table == nullptr) Fail(path, *section, "[hosts] must be a table of [hosts.NAME] tables");
  for (auto&& [name, node] : *table) {
    const std::string where = fmt::format("[hosts.{}]", name.str());
    const toml::table* t = node.as_table();
    if (t == nullptr) Fail(path, node, where + " must be a table");
    HostSpec host;
    for (auto&& [key, value] : *t) {
      if (key.str() == "interface")
        host.interface = RequireString(path, value, where + " interface");
      else
        Fail(path, value, fmt::format("unknown key {} {} (known: interface)", where, key.str()));
    }
    hosts[std::string(name.str())] = host;
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
        throw std::runtime_error(
            fmt::format("{}: member {} requires \"{}\", which is no member", group.path, m.name, r));
      if (host_of[r] != m.host) {
        throw std::runtime_error(
            fmt::format("{}: member {} (host {}) requires {} on host {}: systemd orders units of one host only",
                        group.path, m.name, m.host, r, host_of[r]));
      }
    }
    if (!group.hosts.empty() && !group.hosts.count(m.host)) {
      throw std::runtime_error(
          fmt::format("{}: member {} is on host {}, which [hosts] does not list", group.path, m.name, m.host));
    }
  }
  const std::vector<std::string> hosts = group.MemberHosts();
  if (hosts.size() > 1 && group.session_id == 0) {
    throw std::runtime_error(
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

GroupSpec GroupOf(const toml::table& root, const std::string& path, const VariableLookup& variables) {
  GroupSpec group;
  group.path = path;
  ReadGroupSection(path, root, &group);
  group.members = ReadMembers(path, root, variables);
  if (group.name.empty()) group.name = path;
  group.hosts = ReadHosts(path, root);
  CheckMembers(group);
  group.transport = ReadTransportSection(root, path, HostsOf(group.members));
  return group;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
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
  toml::table root;
  try {
    root = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}:{}:{}: {}", origin, e.source().begin.line, e.source().begin.column, e.description()));
  }
  return GroupOf(root, origin, variables);
}

GroupSpec ReadGroupFile(const std::string& path, const VariableLookup& variables) {
  return ParseGroupFile(ReadText(path), path, variables);
}

TransportConfig LoadTransportConfig(const std::string& path) { return ReadGroupFile(path).transport; }

}  // namespace edsp
