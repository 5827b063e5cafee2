#pragma once
// The launcher's voice on the group's bus: EDSP_FAULT and EDSP_STATUS over
// LCM (never shm: the launcher is no member of the routes), as node
// "launcher", or "launcher@<host>" for one host's members (one per host).

#include <chrono>
#include <cstdint>
#include <string>

#include "edsp/node/node_reporting.h"
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
  // The time from one watch step's start to the next's (10 ms when on
  // time): EDSP_STATUS's loop_*_us for the launcher, so a report that came
  // late says how late the launcher itself ran.
  void RecordStepInterval(std::chrono::nanoseconds interval) { reporting_.status().RecordLoop(interval); }

 private:
  std::string node_;
  Bus bus_;
  NodeReporting reporting_;
};

}  // namespace edsp
