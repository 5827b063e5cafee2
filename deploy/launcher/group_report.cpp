#include "group_report.h"

#include <fmt/format.h>

#include "edsp/node/fault.h"

namespace edsp {

namespace {
TransportConfig LcmOnly(const GroupSpec& group) {
  TransportConfig config = group.transport;
  config.channels.clear();
  return config;
}
}  // namespace

GroupReport::GroupReport(const GroupSpec& group, const std::string& host)
    : node_(host.empty() ? "launcher" : "launcher@" + host), bus_(LcmOnly(group)), reporting_(bus_, node_) {}

// Each member's fault is its own event: two members dying in one instant are
// two faults, never one held back behind the other.
void GroupReport::Fault(const std::string& member, std::int8_t severity, const std::string& reason) {
  reporting_.Announce(
      MakeFault(node_, "", FaultCode::kProcess, severity, fmt::format("member {}: {}", member, reason), UtimeNow()));
  reporting_.status().CountOut();
}

void GroupReport::Tick(bool healthy) {
  reporting_.status().SetState(healthy ? node_status_t::STATE_RUNNING : node_status_t::STATE_FAULT);
  reporting_.StatusTick(UtimeNow(), 0);
}

}  // namespace edsp
