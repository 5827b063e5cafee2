#pragma once
// The cueing's transport delay, sample by sample: from a vehicle packet
// leaving its sender to the bridge's cycle that wrote the drives a command
// made from it. Each link is in the group's log: a cue and the planner's
// setpoint that follows it carry the packet's sequence (`segment`,
// VehicleSequenceAsSegment), a leg command the setpoint's seq, a leg state
// the last command the bridge wrote. 14 CFR Part 60 bounds this chain
// (150 ms for airplanes at levels C/D); edsp's target is 5 ms at p99.

#include <cstdint>
#include <vector>

namespace edsp {

struct SentSample {
  std::uint32_t sequence = 0;
  std::int64_t sent_utime = 0;  // the host's wall clock
};
struct CueingSetpointLink {  // an EDSP_SETPOINT while cueing, in log order
  std::int64_t seq = 0;
  std::int32_t segment = 0;       // the vehicle packet's sequence it comes from
  std::int64_t logged_utime = 0;  // when the logger received it
};
struct CommandLink {  // an EDSP_LEG_COMMAND
  std::int64_t seq = 0;
  std::int64_t setpoint_seq = 0;
};
// An EDSP_LEG_STATE: the last command the bridge wrote to the drives, and
// when the logger received it. The bridge publishes it right after the
// write, but stamps it with the instant its drive reading describes (before
// the write): the receipt bounds the write from above by one message's
// transport, so the delay is never understated.
struct DriveWrite {
  std::int64_t utime = 0;
  std::int64_t command_seq = 0;
};

struct CueingDelays {
  std::size_t sent = 0;
  std::vector<double> delays_s;       // one per sample traced to a drive write, in sequence order
  double Percentile(double p) const;  // nearest rank, p in [0, 1]; 0 when none traced
};

// Each sent sample's delay, in a log of one run of each node (every seq
// grows): the first setpoint that came from it, logged after it was sent
// (a sender restarted in the same log numbers its packets from 1 again; a
// log of another run traces nothing) (a sample
// that a newer one overtook before any cue used it has none, and is not
// traced), the first command for that setpoint or a later one, the first
// drive write of that command or a later one.
CueingDelays TraceCueingDelays(const std::vector<SentSample>& sent, const std::vector<CueingSetpointLink>& setpoints,
                               const std::vector<CommandLink>& commands, const std::vector<DriveWrite>& writes);

}  // namespace edsp
