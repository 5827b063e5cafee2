#pragma once
// A node's two reporting channels on the bus: throttled EDSP_FAULT and its
// EDSP_STATUS once a second.

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

class NodeReporting {
 public:
  // Set-up: advertises EDSP_FAULT and EDSP_STATUS (may throw TransportError).
  NodeReporting(Bus& bus, const std::string& node);

  // Publishes the fault unless the throttle holds it back (never info).
  void Fault(fault_t fault);
  // Publishes the fault, never held back: for events that are rare by
  // construction and each its own (a transition, a member of a group that
  // died), which a throttle keyed by channel and code would merge.
  void Announce(const fault_t& fault);
  NodeStatus& status() { return status_; }
  // Publishes EDSP_STATUS when a second has passed since the last one.
  void StatusTick(std::int64_t now_utime, std::int64_t deadline_misses);
  // An EDSP_FAULT (undecodable, throttled) for packets on `channel` that did
  // not decode since the last call: a foreign or truncated packet is refused
  // by the Bus, and the rig's operator must hear of it. Costs nothing (no
  // allocation) on a channel that never had one: loops call it every cycle.
  void ReportUndecodable(std::string_view channel, const ChannelCounters& in, std::int64_t now_utime);

 private:
  Bus::Publisher<fault_t> faults_;
  Bus::Publisher<node_status_t> status_out_;
  FaultThrottle throttle_;
  NodeStatus status_;
  std::string node_;
  std::map<std::string, std::uint64_t, std::less<>> reported_decode_errors_;
};

}  // namespace edsp
