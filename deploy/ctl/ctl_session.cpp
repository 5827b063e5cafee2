#include "ctl_session.h"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/node/group_file.h"
#include "edsp/reply_codes.h"

namespace edsp::ctl {

int ExitFor(std::int8_t reply_code) {
  switch (FamilyOf(reply_code)) {
    case ReplyFamily::kDone: return kDone;
    case ReplyFamily::kRefused: return kRefused;
    case ReplyFamily::kFailed: return kError;
  }
  return kError;
}

void AddCommonOptions(CLI::App* cmd, CtlOptions* o) {
  cmd->add_option("--session-id", o->session, "the group's session, or auto (from its traffic)");
  cmd->add_option("--operator", o->operator_name, "who asks, for the log");
  cmd->add_option("--group", o->group_file, "take the LCM URL from this group file");
  cmd->add_option("--lcm-url", o->lcm_url, "LCM URL (default: the edsp default, host-only)");
  cmd->add_option("--answer-timeout-s", o->timeout_s, "how long to wait for the group's traffic and the reply")
      ->check(CLI::Range(0.1, 600.0));
}

TransportConfig Transport(const CtlOptions& o) {
  TransportConfig config = o.group_file.empty() ? TransportConfig{} : LoadTransportConfig(o.group_file);
  if (!o.lcm_url.empty()) config.lcm_url = o.lcm_url;
  config.channels.clear();  // the operator's requests and the replies all travel on LCM
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

std::string OperatorName(const CtlOptions& o) {
  if (!o.operator_name.empty()) return o.operator_name;
  const char* user = std::getenv("USER");
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  return fmt::format("{}@{} (edsp-ctl)", user != nullptr ? user : "operator", host);
}

}  // namespace edsp::ctl
