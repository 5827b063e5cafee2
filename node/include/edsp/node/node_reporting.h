#pragma once
// A node's two reporting channels on the bus: throttled EDSP_FAULT and its
// EDSP_STATUS once a second.

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

// Whether a watched input's losses (seq gaps, overruns) are the node's
// status's drops: those of the stream the node follows.
enum class InputLosses { kNotCounted, kCountedAsDrops };

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
  // An input the node reads from `bus`: StatusTick reports its packets that
  // did not decode, and with kCountedAsDrops its losses are the status's
  // drops. Returns its counters (they live as long as the bus).
  const ChannelCounters& WatchInput(Bus& bus, const std::string& channel,
                                    InputLosses losses = InputLosses::kNotCounted);
  // Once a cycle or poll: the watched inputs reported, then EDSP_STATUS
  // when a second has passed since the last one.
  void StatusTick(std::int64_t now_utime, std::int64_t deadline_misses);
  // The end of a clocked loop's cycle begun at `began`: its busy time
  // recorded (the status's loop times), then StatusTick.
  void EndCycle(std::chrono::steady_clock::time_point began, std::int64_t now_utime, std::int64_t deadline_misses);

 private:
  struct WatchedInput {
    std::string channel;
    const ChannelCounters* in;
    InputLosses losses;
  };
  // An EDSP_FAULT (undecodable, throttled) for packets on `channel` that did
  // not decode since the last call: a foreign or truncated packet is refused
  // by the Bus, and the rig's operator must hear of it. Costs nothing (no
  // allocation) on a channel that never had one: called every cycle.
  void ReportUndecodable(std::string_view channel, const ChannelCounters& in, std::int64_t now_utime);
  void ReportInputs(std::int64_t now_utime);

  std::vector<WatchedInput> inputs_;
  Bus::Publisher<fault_t> faults_;
  Bus::Publisher<node_status_t> status_out_;
  FaultThrottle throttle_;
  NodeStatus status_;
  std::string node_;
  std::map<std::string, std::uint64_t, std::less<>> reported_decode_errors_;
};

}  // namespace edsp
