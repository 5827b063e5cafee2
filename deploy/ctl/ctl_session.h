#pragma once
// What every edsp-ctl command shares: the bus it talks on, the session of
// the group it talks to (given, or found from the group's own traffic),
// and who the operator is, for the log.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "edsp/transport/bus.h"

namespace edsp::ctl {

using Clock = std::chrono::steady_clock;

struct CtlOptions {
  std::string session = "auto";
  std::string operator_name;
  std::string group_file;
  std::string lcm_url;
  double timeout_s = 2.0;  // each wait: for the group's traffic, for the answer
};

Clock::time_point Deadline(double seconds);
// The group's LCM: the operator's commands and the answers all travel on it.
TransportConfig Transport(const CtlOptions& o);
// --session-id as given (none for "auto"); throws naming a malformed one.
std::optional<std::int64_t> GivenSession(const CtlOptions& o);
// --session-id, or with "auto" the one session whose leg commands or
// setpoints are on the bus within the timeout (none or several: an error).
std::int64_t SessionId(Bus& bus, const CtlOptions& o);
// "user@host (edsp-ctl)", or --operator.
std::string OperatorName(const CtlOptions& o);

}  // namespace edsp::ctl
