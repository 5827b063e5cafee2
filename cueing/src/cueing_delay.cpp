#include "edsp/cueing/cueing_delay.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

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
  std::unordered_map<std::int32_t, std::int64_t> first_setpoint;  // segment → the first setpoint's seq
  for (const CueingSetpointLink& s : setpoints) first_setpoint.emplace(s.segment, s.seq);
  CueingDelays out;
  out.sent = sent.size();
  // The samples go in sequence order and the links in the log's, each
  // growing: each search starts where the last one ended.
  auto command = commands.begin();
  auto write = writes.begin();
  for (const SentSample& sample : sent) {
    const auto found = first_setpoint.find(VehicleSequenceAsSegment(sample.sequence));
    if (found == first_setpoint.end()) continue;
    command =
        std::find_if(command, commands.end(), [&](const CommandLink& c) { return c.setpoint_seq >= found->second; });
    if (command == commands.end()) continue;
    write = std::find_if(write, writes.end(), [&](const DriveWrite& w) { return w.command_seq >= command->seq; });
    if (write == writes.end()) continue;
    out.delays_s.push_back(static_cast<double>(write->utime - sample.sent_utime) * 1e-6);
  }
  return out;
}

}  // namespace edsp
