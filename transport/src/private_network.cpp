#include "edsp/transport/private_network.h"

#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "edsp/transport/error.h"

namespace edsp {

namespace {

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// Without root: a user namespace in which we are root, mapped to our uid.
bool EnterUserAndNetworkNamespace() {
  const uid_t uid = ::getuid();
  const gid_t gid = ::getgid();
  if (::unshare(CLONE_NEWUSER | CLONE_NEWNET) != 0) return false;
  WriteFile("/proc/self/setgroups", "deny");
  WriteFile("/proc/self/uid_map", fmt::format("0 {} 1", uid));
  WriteFile("/proc/self/gid_map", fmt::format("0 {} 1", gid));
  return true;
}

}  // namespace

void EnterPrivateNetworkNamespace() {
  if (::unshare(CLONE_NEWNET) != 0) {
    const int error = errno;
    if (!EnterUserAndNetworkNamespace()) {
      throw TransportError(
          fmt::format("cannot create a private network namespace ({}): run as root, or enable "
                      "unprivileged user namespaces",
                      std::strerror(error)));
    }
  }
  const int rc = std::system(
      "ip link set lo up && ip route add 224.0.0.0/4 dev lo 2>/dev/null || "
      "ip route replace 224.0.0.0/4 dev lo");
  if (rc != 0) {
    throw TransportError(
        "private network namespace: could not bring up lo with a multicast route (is iproute2 "
        "installed?)");
  }
}

}  // namespace edsp
