#include "edsp/node/session_discovery.h"

#include <chrono>
#include <memory>
#include <set>
#include <string>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

std::int64_t DiscoverSession(Bus& bus, double timeout_s) {
  using Clock = std::chrono::steady_clock;
  // Bus has no unsubscribe: the handlers share ownership of what they fill.
  auto seen = std::make_shared<std::set<std::int64_t>>();
  bus.Subscribe<leg_command_t>(channel::kLegCommand, [seen](const leg_command_t& c) { seen->insert(c.session_id); });
  bus.Subscribe<pose_setpoint_t>(channel::kSetpoint, [seen](const pose_setpoint_t& s) { seen->insert(s.session_id); });
  const std::set<std::int64_t>& sessions = *seen;
  const auto until =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (Clock::now() < until && sessions.empty()) bus.Handle(std::chrono::milliseconds(50));
  bus.Handle(std::chrono::milliseconds(50));  // one more round: a second group shows itself
  if (sessions.empty()) {
    throw SessionNotFound(
        fmt::format("no leg commands or setpoints on {} within {} s: is the group running "
                    "on this network? (or give the session id)",
                    bus.config().lcm_url, timeout_s));
  }
  if (sessions.size() > 1) {
    std::string list;
    for (std::int64_t s : sessions) list += (list.empty() ? "" : ", ") + std::to_string(s);
    throw SessionNotFound("several groups on the bus (sessions " + list + "): give the session id");
  }
  return *sessions.begin();
}

}  // namespace edsp
