#include "multicast_route.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {

std::string MulticastAddress(const std::string& lcm_url) {
  const std::string scheme = "udpm://";
  if (lcm_url.rfind(scheme, 0) != 0) return "";
  const std::size_t end = lcm_url.find_first_of(":?", scheme.size());
  return lcm_url.substr(scheme.size(), end == std::string::npos ? std::string::npos : end - scheme.size());
}

// A connected UDP socket takes the source address the routing table picks
// for the destination; the interface holding that address is the answer.
// Nothing is sent.
std::string MulticastRouteInterface(const std::string& group_address, std::string* error) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(7667);
  if (::inet_pton(AF_INET, group_address.c_str(), &to.sin_addr) != 1) {
    throw std::runtime_error("multicast address \"" + group_address + "\" is not an IPv4 address");
  }
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  sockaddr_in from{};
  socklen_t length = sizeof from;
  const bool routed = ::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) == 0 &&
                      ::getsockname(fd, reinterpret_cast<sockaddr*>(&from), &length) == 0;
  const int connect_errno = errno;
  ::close(fd);
  if (!routed) {
    *error = std::string("no route to ") + group_address + " (" + std::strerror(connect_errno) + ")";
    return "";
  }
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) != 0) throw std::runtime_error(std::string("getifaddrs: ") + std::strerror(errno));
  std::string name;
  for (const ifaddrs* a = list; a != nullptr; a = a->ifa_next) {
    if (a->ifa_addr == nullptr || a->ifa_addr->sa_family != AF_INET) continue;
    const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
    if (in->sin_addr.s_addr == from.sin_addr.s_addr) {
      name = a->ifa_name;
      break;
    }
  }
  ::freeifaddrs(list);
  if (name.empty()) {
    char text[INET_ADDRSTRLEN] = {0};
    ::inet_ntop(AF_INET, &from.sin_addr, text, sizeof text);
    *error = std::string("the route to ") + group_address + " leaves from " + text + ", which no interface holds";
  }
  return name;
}

void CheckMulticastInterface(const GroupSpec& group, const std::string& host) {
  const auto it = group.hosts.find(host);
  if (it == group.hosts.end() || it->second.interface.empty()) return;
  const std::string url = group.transport.lcm_url;
  const std::string address = MulticastAddress(url);
  if (address.empty()) return;
  std::string error;
  const std::string interface = MulticastRouteInterface(address, &error);
  if (interface != it->second.interface) {
    throw std::runtime_error(
        fmt::format("{}: [hosts.{}] interface = \"{}\", but the route to the LCM group {} {}; add one with "
                    "`ip route add 224.0.0.0/4 dev {}` (docs/multihost.md)",
                    group.path, host, it->second.interface, address,
                    interface.empty() ? error : "leaves by " + interface, it->second.interface));
  }
}

}  // namespace edsp
