#include "edsp/transport/transport_config.h"

#include <cstdlib>

#include <fmt/format.h>

#include "edsp/transport/error.h"
#include "edsp/transport/host_routes.h"
#include "edsp/transport/transport_section.h"

namespace edsp {

const char* ChannelPathName(ChannelPath path) {
  switch (path) {
    case ChannelPath::kLcm: return "lcm";
    case ChannelPath::kShm: return "shm";
    case ChannelPath::kBoth: return "both";
  }
  return "invalid";
}

const ChannelRoute& TransportConfig::Route(const std::string& channel) const {
  static const ChannelRoute kLcmRoute;
  const auto it = channels.find(channel);
  return it == channels.end() ? kLcmRoute : it->second;
}

std::string TransportConfig::SegmentName(const std::string& channel) const { return shm_prefix + "." + channel; }

namespace {

[[noreturn]] void Fail(const std::string& origin, const toml::node& node, const std::string& what) {
  throw TransportError(fmt::format("{}:{}: {}", origin, node.source().begin.line, what));
}

std::uint32_t ReadCount(const toml::table& table, const char* key, std::uint32_t fallback, std::uint32_t max,
                        const std::string& where, const std::string& origin) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return fallback;
  const auto value = node->value<std::int64_t>();
  if (!node->is_integer() || *value < 1 || *value > max) {
    Fail(origin, *node, fmt::format("{} {} must be an integer in 1..{}", where, key, max));
  }
  return static_cast<std::uint32_t>(*value);
}

ChannelRoute ReadRoute(const toml::table& table, const std::string& channel, const std::string& origin) {
  const std::string where = fmt::format("[transport.channels.{}]", channel);
  for (auto&& [key, node] : table) {
    const std::string k(key.str());
    if (k != "path" && k != "mirror_every" && k != "slots" && k != "slot_size_bytes" && k != "writer" &&
        k != "readers") {
      Fail(origin, node,
           fmt::format("unknown key {} {} (known: path, mirror_every, slots, slot_size_bytes, "
                       "writer, readers)",
                       where, k));
    }
  }
  ChannelRoute route;
  if (const toml::node* writer = table.get("writer")) {
    if (!writer->is_string() || writer->value_or(std::string()).empty()) {
      Fail(origin, *writer, where + " writer must be a member's name");
    }
    route.writer = *writer->value<std::string>();
  }
  if (const toml::node* readers = table.get("readers")) {
    const toml::array* list = readers->as_array();
    if (list == nullptr) Fail(origin, *readers, where + " readers must be an array of member names");
    for (const toml::node& r : *list) {
      if (!r.is_string()) Fail(origin, r, where + " readers must be an array of member names");
      route.readers.push_back(*r.value<std::string>());
    }
  }
  if (const toml::node* path = table.get("path")) {
    const std::string text = path->value_or(std::string());
    if (text == "lcm") {
      route.path = ChannelPath::kLcm;
    } else if (text == "shm") {
      route.path = ChannelPath::kShm;
    } else if (text == "both") {
      route.path = ChannelPath::kBoth;
    } else {
      Fail(origin, *path, fmt::format("{} path = \"{}\" must be lcm, shm or both", where, text));
    }
  }
  route.mirror_every = ReadCount(table, "mirror_every", 1, 1000000, where, origin);
  route.slots = ReadCount(table, "slots", route.slots, 65536, where, origin);
  if ((route.slots & (route.slots - 1)) != 0 || route.slots < 2) {
    Fail(origin, *table.get("slots"), fmt::format("{} slots = {} must be a power of two ≥ 2", where, route.slots));
  }
  route.slot_size_bytes = ReadCount(table, "slot_size_bytes", route.slot_size_bytes, 16u << 20, where, origin);
  return route;
}

}  // namespace

TransportConfig ReadTransportSection(const toml::table& file, const std::string& origin,
                                     const HostAssignment& member_hosts) {
  TransportConfig config;
  config.member_hosts = member_hosts;
  const toml::table* transport = file["transport"].as_table();
  if (transport == nullptr) {
    CheckHostRoutes(config, origin);  // the defaults are host-only
    return config;
  }
  for (auto&& [key, node] : *transport) {
    const std::string k(key.str());
    if (k == "lcm_url") {
      if (!node.is_string()) Fail(origin, node, "[transport] lcm_url must be a string");
      config.lcm_url = *node.value<std::string>();
    } else if (k == "shm_prefix") {
      const std::string prefix = node.value_or(std::string());
      if (prefix.empty() || prefix.find('/') != std::string::npos) {
        Fail(origin, node, "[transport] shm_prefix must be a non-empty name without '/'");
      }
      config.shm_prefix = prefix;
    } else if (k == "shm_permissions") {
      const std::string mode = node.value_or(std::string());
      char* end = nullptr;
      const long value = std::strtol(mode.c_str(), &end, 8);
      if (mode.empty() || *end != '\0' || value < 0 || value > 0777 || (value & 0600) != 0600) {
        Fail(origin, node,
             fmt::format("[transport] shm_permissions = \"{}\" must be an octal mode like "
                         "\"0600\" or \"0660\" that the owner can read and write",
                         mode));
      }
      config.shm_permissions = static_cast<mode_t>(value);
    } else if (k == "channels") {
      const toml::table* channels = node.as_table();
      if (channels == nullptr) Fail(origin, node, "[transport.channels] must be a table");
      for (auto&& [name, route] : *channels) {
        const toml::table* table = route.as_table();
        if (table == nullptr) {
          Fail(origin, route, fmt::format("[transport.channels.{}] must be a table", name.str()));
        }
        config.channels[std::string(name.str())] = ReadRoute(*table, std::string(name.str()), origin);
      }
    } else {
      Fail(origin, node, fmt::format("unknown key [transport] {}", k));
    }
  }
  CheckHostRoutes(config, origin);
  return config;
}

TransportConfig ParseTransportConfig(const std::string& toml_text, const std::string& origin,
                                     const HostAssignment& member_hosts) {
  toml::table file;
  try {
    file = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    throw TransportError(
        fmt::format("{}:{}:{}: {}", origin, e.source().begin.line, e.source().begin.column, e.description()));
  }
  return ReadTransportSection(file, origin, member_hosts);
}

}  // namespace edsp
