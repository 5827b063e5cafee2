#include "edsp/transport/transport_config.h"

#include <cstdlib>

#include <fmt/format.h>

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

std::uint32_t ReadCount(const ConfigSection& route, const char* key, std::uint32_t fallback, std::uint32_t max) {
  return static_cast<std::uint32_t>(route.Integer(key, fallback, 1, max));
}

ChannelPath ReadPath(const ConfigSection& route) {
  const std::string text = route.String("path", "lcm");
  if (text == "lcm") return ChannelPath::kLcm;
  if (text == "shm") return ChannelPath::kShm;
  if (text == "both") return ChannelPath::kBoth;
  route.Fail("path", fmt::format("{} path = \"{}\" must be lcm, shm or both", route.label(), text));
}

ChannelRoute ReadRoute(const ConfigSection& table) {
  table.RejectUnknownKeys({"path", "mirror_every", "slots", "slot_size_bytes", "writer", "readers"});
  ChannelRoute route;
  if (table.Has("writer")) {
    route.writer = table.String("writer", "");
    if (route.writer.empty()) table.Fail("writer", fmt::format("{} writer must be a member's name", table.label()));
  }
  route.readers = table.Strings("readers");
  route.path = ReadPath(table);
  route.mirror_every = ReadCount(table, "mirror_every", 1, 1000000);
  route.slots = ReadCount(table, "slots", route.slots, 65536);
  if ((route.slots & (route.slots - 1)) != 0 || route.slots < 2) {
    table.Fail("slots", fmt::format("{} slots = {} must be a power of two ≥ 2", table.label(), route.slots));
  }
  route.slot_size_bytes = ReadCount(table, "slot_size_bytes", route.slot_size_bytes, 16u << 20);
  return route;
}

mode_t ReadPermissions(const ConfigSection& transport, mode_t fallback) {
  if (!transport.Has("shm_permissions")) return fallback;
  const std::string mode = transport.String("shm_permissions", "");
  char* end = nullptr;
  const long value = std::strtol(mode.c_str(), &end, 8);
  if (mode.empty() || *end != '\0' || value < 0 || value > 0777 || (value & 0600) != 0600) {
    transport.Fail("shm_permissions", fmt::format("[transport] shm_permissions = \"{}\" must be an octal mode like "
                                                  "\"0600\" or \"0660\" that the owner can read and write",
                                                  mode));
  }
  return static_cast<mode_t>(value);
}

}  // namespace

TransportConfig ReadTransportSection(const ConfigFile& file, const HostAssignment& member_hosts) {
  TransportConfig config;
  config.member_hosts = member_hosts;
  const ConfigSection transport = file.Section("transport");
  transport.RejectUnknownKeys({"lcm_url", "shm_prefix", "shm_permissions", "channels"});
  config.lcm_url = transport.String("lcm_url", config.lcm_url);
  config.shm_prefix = transport.String("shm_prefix", config.shm_prefix);
  if (config.shm_prefix.empty() || config.shm_prefix.find('/') != std::string::npos) {
    transport.Fail("shm_prefix", "[transport] shm_prefix must be a non-empty name without '/'");
  }
  config.shm_permissions = ReadPermissions(transport, config.shm_permissions);
  for (const auto& [channel, route] : transport.Table("channels").Tables()) config.channels[channel] = ReadRoute(route);
  CheckHostRoutes(config, file.origin());
  return config;
}

TransportConfig ParseTransportConfig(const std::string& toml_text, const std::string& origin,
                                     const HostAssignment& member_hosts) {
  return ReadTransportSection(ConfigFile::Parse(toml_text, origin), member_hosts);
}

}  // namespace edsp
