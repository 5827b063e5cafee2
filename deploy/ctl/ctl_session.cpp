#include "ctl_session.h"

#include <unistd.h>

#include <cstdlib>
#include <memory>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

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

// The session of the group commanding the platform, from its own traffic.
// The handlers stay subscribed for the bus's life (Bus has no unsubscribe),
// so they share ownership of what they write to.
namespace {

std::int64_t DiscoverSession(Bus& bus, const CtlOptions& o) {
  auto seen = std::make_shared<std::set<std::int64_t>>();
  bus.Subscribe<leg_command_t>(channel::kLegCommand, [seen](const leg_command_t& c) { seen->insert(c.session_id); });
  bus.Subscribe<pose_setpoint_t>(channel::kSetpoint, [seen](const pose_setpoint_t& s) { seen->insert(s.session_id); });
  const std::set<std::int64_t>& sessions = *seen;
  const auto until = Deadline(o.timeout_s);
  while (Clock::now() < until && sessions.empty()) bus.Handle(std::chrono::milliseconds(50));
  bus.Handle(std::chrono::milliseconds(50));  // one more round: a second group shows itself
  if (sessions.empty()) {
    throw std::runtime_error(fmt::format("no leg commands or setpoints on {} within {} s: is the group running "
                                         "on this network? (or give --session-id)", bus.config().lcm_url, o.timeout_s));
  }
  if (sessions.size() > 1) {
    std::string list;
    for (std::int64_t s : sessions) list += (list.empty() ? "" : ", ") + std::to_string(s);
    throw std::runtime_error("several groups on the bus (sessions " + list + "): give --session-id");
  }
  return *sessions.begin();
}

}  // namespace

std::int64_t SessionId(Bus& bus, const CtlOptions& o) {
  if (o.session == "auto") return DiscoverSession(bus, o);
  try {
    std::size_t used = 0;
    const std::int64_t id = std::stoll(o.session, &used);
    if (used == o.session.size() && id >= 0) return id;
  } catch (const std::exception&) {
  }
  throw std::runtime_error("--session-id " + o.session + ": give a non-negative integer or auto");
}


std::string OperatorName(const CtlOptions& o) {
  if (!o.operator_name.empty()) return o.operator_name;
  const char* user = std::getenv("USER");
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  return fmt::format("{}@{} (edsp-ctl)", user != nullptr ? user : "operator", host);
}

}  // namespace edsp::ctl
