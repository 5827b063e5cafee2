#include "edsp/transport/host_routes.h"

#include <algorithm>
#include <cstdlib>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "edsp/transport/error.h"

namespace edsp {

namespace {

std::string HostOf(const TransportConfig& config, const std::string& member) {
  const auto it = config.member_hosts.find(member);
  return it == config.member_hosts.end() ? std::string() : it->second;
}

// Is any reader of `route` (the listed ones, or else any member) on a host
// other than the writer's?
bool HasRemoteReader(const TransportConfig& config, const ChannelRoute& route, const std::string& writer_host) {
  if (route.readers.empty()) {
    return std::any_of(config.member_hosts.begin(), config.member_hosts.end(),
                       [&](const auto& member) { return member.second != writer_host; });
  }
  return std::any_of(route.readers.begin(), route.readers.end(),
                     [&](const std::string& r) { return HostOf(config, r) != writer_host; });
}

}  // namespace

std::vector<std::string> GroupHosts(const TransportConfig& config) {
  std::set<std::string> hosts;
  for (const auto& member : config.member_hosts) hosts.insert(member.second);
  return {hosts.begin(), hosts.end()};
}

int LcmUrlTtl(const std::string& url) {
  const std::size_t query = url.find('?');
  if (query == std::string::npos) return 0;
  std::size_t at = query + 1;
  while (at < url.size()) {
    const std::size_t end = std::min(url.find('&', at), url.size());
    const std::string option = url.substr(at, end - at);
    if (option.rfind("ttl=", 0) == 0) {
      const std::string value = option.substr(4);
      char* stop = nullptr;
      const long ttl = std::strtol(value.c_str(), &stop, 10);
      if (value.empty() || *stop != '\0' || ttl < 0 || ttl > 255) {
        throw TransportError(fmt::format("LCM URL {}: ttl={} must be an integer 0..255", url, value));
      }
      return static_cast<int>(ttl);
    }
    at = end + 1;
  }
  return 0;
}

void CheckHostRoutes(const TransportConfig& config, const std::string& origin) {
  const std::vector<std::string> hosts = GroupHosts(config);
  if (hosts.size() < 2) return;
  if (config.lcm_url.rfind("udpm://", 0) == 0 && LcmUrlTtl(config.lcm_url) < 1) {
    throw TransportError(
        fmt::format("{}: [transport] lcm_url = \"{}\" keeps LCM on one host (ttl=0), but the members run on "
                    "{} hosts ({}): set ttl=1 for one network segment (more only through multicast routers)",
                    origin, config.lcm_url, hosts.size(), fmt::join(hosts, ", ")));
  }
  for (const auto& [channel, route] : config.channels) {
    if (route.path == ChannelPath::kLcm) continue;
    const std::string where = fmt::format("[transport.channels.{}]", channel);
    if (route.writer.empty()) {
      throw TransportError(
          fmt::format("{}: {} path = \"{}\" in a group spanning hosts ({}) needs writer = \"<member>\": "
                      "shared memory only joins members of the writer's host",
                      origin, where, ChannelPathName(route.path), fmt::join(hosts, ", ")));
    }
    for (const std::string& name : route.readers) {
      if (!config.member_hosts.count(name)) {
        throw TransportError(fmt::format("{}: {} readers: \"{}\" is no member of the group", origin, where, name));
      }
    }
    if (!config.member_hosts.count(route.writer)) {
      throw TransportError(
          fmt::format("{}: {} writer = \"{}\" is no member of the group", origin, where, route.writer));
    }
  }
}

TransportConfig RoutesForMember(const TransportConfig& group, const std::string& member) {
  TransportConfig config = group;
  if (GroupHosts(group).size() < 2) return config;
  const std::string host = HostOf(group, member);
  for (auto& [channel, route] : config.channels) {
    if (route.path == ChannelPath::kLcm) continue;
    const std::string writer_host = HostOf(group, route.writer);
    if (member == route.writer) {
      if (HasRemoteReader(group, route, writer_host)) {
        route.path = ChannelPath::kBoth;  // shm for this host, every message on LCM for the others
        route.mirror_every = 1;
      }
    } else if (host.empty() || host != writer_host) {
      route.path = ChannelPath::kLcm;
    }
  }
  return config;
}

}  // namespace edsp
