#include "edsp/cueing/cueing_delay.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "edsp/cueing/vehicle_packet.h"

namespace edsp {

double CueingDelays::Percentile(double p) const {
  if (delays_s.empty()) return 0.0;
  std::vector<double> sorted = delays_s;
  std::sort(sorted.begin(), sorted.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

CueingDelays TraceCueingDelays(const std::vector<SentSample>& sent, const std::vector<CueingSetpointLink>& setpoints,
                               const std::vector<CommandLink>& commands, const std::vector<DriveWrite>& writes) {
  // segment → its setpoints in log order: (logged, seq)
  std::unordered_map<std::int32_t, std::vector<std::pair<std::int64_t, std::int64_t>>> by_segment;
  for (const CueingSetpointLink& s : setpoints) by_segment[s.segment].emplace_back(s.logged_utime, s.seq);
  CueingDelays out;
  out.sent = sent.size();
  // The samples go in sequence order and the links in the log's, each
  // growing: each search starts where the last one ended.
  auto command = commands.begin();
  auto write = writes.begin();
  for (const SentSample& sample : sent) {
    const auto found = by_segment.find(VehicleSequenceAsSegment(sample.sequence));
    if (found == by_segment.end()) continue;
    const auto after_send = std::find_if(found->second.begin(), found->second.end(),
                                         [&](const auto& logged) { return logged.first >= sample.sent_utime; });
    if (after_send == found->second.end()) continue;
    const std::int64_t setpoint_seq = after_send->second;
    command =
        std::find_if(command, commands.end(), [&](const CommandLink& c) { return c.setpoint_seq >= setpoint_seq; });
    if (command == commands.end()) continue;
    write = std::find_if(write, writes.end(), [&](const DriveWrite& w) { return w.command_seq >= command->seq; });
    if (write == writes.end()) continue;
    out.delays_s.push_back(static_cast<double>(write->utime - sample.sent_utime) * 1e-6);
  }
  return out;
}

}  // namespace edsp
