#include "group_report.h"

#include <fmt/format.h>

#include "edsp/channels.h"
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
    : node_(host.empty() ? "launcher" : "launcher@" + host),
      bus_(LcmOnly(group)),
      faults_(bus_.Advertise<fault_t>(channel::kFault)),
      status_out_(bus_.Advertise<node_status_t>(channel::kStatus)),
      status_(node_) {
  status_.SetState(node_status_t::STATE_RUNNING);
}

void GroupReport::Fault(const std::string& member, std::int8_t severity, const std::string& reason) {
  faults_.Publish(
      MakeFault(node_, "", FaultCode::kProcess, severity, fmt::format("member {}: {}", member, reason), UtimeNow()));
  status_.CountOut();
}

void GroupReport::Tick(bool healthy) {
  status_.SetState(healthy ? node_status_t::STATE_RUNNING : node_status_t::STATE_FAULT);
  const std::int64_t now = UtimeNow();
  if (status_.Due(now)) status_out_.Publish(status_.Report(now, 0));
}

}  // namespace edsp
