#include "ctl_session.h"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/node/group_file.h"
#include "edsp/node/session_discovery.h"

namespace edsp::ctl {

Clock::time_point Deadline(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

TransportConfig Transport(const CtlOptions& o) {
  TransportConfig config = o.group_file.empty() ? TransportConfig{} : LoadTransportConfig(o.group_file);
  if (!o.lcm_url.empty()) config.lcm_url = o.lcm_url;
  config.channels.clear();  // the operator's commands and the confirmations all travel on LCM
  return config;
}

std::optional<std::int64_t> GivenSession(const CtlOptions& o) {
  if (o.session == "auto") return std::nullopt;
  try {
    std::size_t used = 0;
    const std::int64_t id = std::stoll(o.session, &used);
    if (used == o.session.size() && id >= 0) return id;
  } catch (const std::exception&) {
  }
  throw std::runtime_error("--session-id " + o.session + ": give a non-negative integer or auto");
}

std::int64_t SessionId(Bus& bus, const CtlOptions& o) {
  const std::optional<std::int64_t> given = GivenSession(o);
  return given ? *given : DiscoverSession(bus, o.timeout_s);
}

std::string OperatorName(const CtlOptions& o) {
  if (!o.operator_name.empty()) return o.operator_name;
  const char* user = std::getenv("USER");
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  return fmt::format("{}@{} (edsp-ctl)", user != nullptr ? user : "operator", host);
}

}  // namespace edsp::ctl
