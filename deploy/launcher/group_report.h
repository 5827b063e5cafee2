#pragma once
// The launcher's voice on the group's bus: EDSP_FAULT and EDSP_STATUS over
// LCM (never shm: the launcher is no member of the routes), as node
// "launcher", or "launcher@<host>" for one host's members (one per host).

#include <cstdint>
#include <string>

#include "edsp/fault_t.hpp"
#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "edsp/transport/bus.h"
#include "group_file.h"

namespace edsp {

class GroupReport {
 public:
  // Opens LCM at the group file's lcm_url; throws TransportError naming it.
  GroupReport(const GroupSpec& group, const std::string& host);
  // EDSP_FAULT (code process) "member NAME: reason".
  void Fault(const std::string& member, std::int8_t severity, const std::string& reason);
  // EDSP_STATUS once a second, and at once when health changes; `healthy`:
  // no member frozen or waiting to restart.
  void Tick(bool healthy);

 private:
  std::string node_;
  Bus bus_;
  Bus::Publisher<fault_t> faults_;
  Bus::Publisher<node_status_t> status_out_;
  NodeStatus status_;
};

}  // namespace edsp
