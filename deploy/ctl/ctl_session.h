#pragma once
// What every edsp-ctl command shares: the bus it talks on, the session of
// the group it talks to (given, or found from the group's own traffic),
// who the operator is, for the log, and the exit codes.
#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "edsp/transport/bus.h"

namespace edsp::ctl {

// docs/interfaces.md §7: 0 done, 2 refused, 3 timed out, 4 halted or
// stopped by another request, 1 any other error (a node that failed).
enum Exit { kDone = 0, kError = 1, kRefused = 2, kTimedOut = 3, kInterrupted = 4 };
// A reply's code (reply_t.CODE_*) as the exit code: by its family.
int ExitFor(std::int8_t reply_code);

struct CtlOptions {
  std::string session = "auto";
  std::string operator_name;
  std::string group_file;
  std::string lcm_url;
  double timeout_s = 2.0;  // each wait: for the group's traffic, for the answer
};

// --session-id, --operator, --group, --lcm-url and --answer-timeout-s on
// `cmd`: on the app (before the command) and on every command (after it).
void AddCommonOptions(CLI::App* cmd, CtlOptions* o);
// The group's LCM: the operator's commands and the answers all travel on it.
TransportConfig Transport(const CtlOptions& o);
// --session-id as given (none for "auto"); throws naming a malformed one.
std::optional<std::int64_t> GivenSession(const CtlOptions& o);
// "user@host (edsp-ctl)", or --operator.
std::string OperatorName(const CtlOptions& o);

}  // namespace edsp::ctl
