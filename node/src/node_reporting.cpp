#include "edsp/node/node_reporting.h"
#include "edsp/channels.h"

#include <fmt/format.h>

namespace edsp {

NodeReporting::NodeReporting(Bus& bus, const std::string& node)
    : faults_(bus.Advertise<fault_t>(channel::kFault)),
      status_out_(bus.Advertise<node_status_t>(channel::kStatus)),
      status_(node),
      node_(node) {
  status_.SetState(node_status_t::STATE_RUNNING);
}

void NodeReporting::Fault(fault_t fault) {
  // Info is a transition (re-armed, rejoined, answering again): rare by
  // construction, and one held back behind a refusal would be lost.
  if (fault.severity == fault_t::SEVERITY_INFO) {
    Announce(fault);
  } else if (throttle_.Admit(&fault)) {
    faults_.Publish(fault);
  }
}

void NodeReporting::Announce(const fault_t& fault) { faults_.Publish(fault); }

const ChannelCounters& NodeReporting::WatchInput(Bus& bus, const std::string& channel, InputLosses losses) {
  const ChannelCounters& in = bus.Counters(channel);
  inputs_.push_back({channel, &in, losses});
  return in;
}

void NodeReporting::StatusTick(std::int64_t now_utime, std::int64_t deadline_misses) {
  ReportInputs(now_utime);
  if (status_.Due(now_utime)) status_out_.Publish(status_.Report(now_utime, deadline_misses));
}

void NodeReporting::EndCycle(std::chrono::steady_clock::time_point began, std::int64_t now_utime,
                             std::int64_t deadline_misses) {
  status_.RecordLoop(std::chrono::steady_clock::now() - began);
  StatusTick(now_utime, deadline_misses);
}

void NodeReporting::ReportInputs(std::int64_t now_utime) {
  std::uint64_t drops = 0;
  bool counted = false;
  for (const WatchedInput& w : inputs_) {
    if (w.losses == InputLosses::kCountedAsDrops) {
      drops += w.in->seq_gaps + w.in->overruns;
      counted = true;
    }
    ReportUndecodable(w.channel, *w.in, now_utime);
  }
  if (counted) status_.SetDrops(static_cast<std::int64_t>(drops));
}

void NodeReporting::ReportUndecodable(std::string_view channel, const ChannelCounters& in, std::int64_t now_utime) {
  if (in.decode_errors == 0) return;
  auto it = reported_decode_errors_.find(channel);
  if (it == reported_decode_errors_.end()) it = reported_decode_errors_.emplace(std::string(channel), 0).first;
  std::uint64_t& reported = it->second;
  if (in.decode_errors <= reported) return;
  Fault(MakeFault(node_, std::string(channel), FaultCode::kUndecodable, fault_t::SEVERITY_WARNING,
                  fmt::format("{} undecodable packets; last: {}", in.decode_errors - reported, in.last_error),
                  now_utime));
  reported = in.decode_errors;
}

}  // namespace edsp
