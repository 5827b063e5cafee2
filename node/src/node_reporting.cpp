#include "edsp/node/node_reporting.h"

namespace edsp {

NodeReporting::NodeReporting(Bus& bus, const std::string& node)
    : faults_(bus.Advertise<fault_t>("EDSP_FAULT")),
      status_out_(bus.Advertise<node_status_t>("EDSP_STATUS")),
      status_(node) {
  status_.SetState(node_status_t::STATE_RUNNING);
}

void NodeReporting::Fault(fault_t fault) {
  if (throttle_.Admit(&fault)) faults_.Publish(fault);
}

void NodeReporting::StatusTick(std::int64_t now_utime, std::int64_t deadline_misses) {
  if (status_.Due(now_utime)) status_out_.Publish(status_.Report(now_utime, deadline_misses));
}

}  // namespace edsp
