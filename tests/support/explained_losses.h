#pragma once
// Which messages a log lost while nothing was backed up. A logger that the
// machine leaves without the CPU overflows its socket, and a publisher that
// stood sends a burst the network may not carry: losses where this run's
// messages waited are the machine's. A loss where the stream flowed (a
// link, a route or a buffer that loses packets all along) is the stack's,
// on any machine.

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "edsp/logger/log_reader.h"
#include "edsp/transport/seq_gap.h"

namespace edsp::test_support {

// A message that came this late, after it was stamped, came out of a
// backlog (or a silence of everything this long went before it).
inline constexpr std::int64_t kStallUs = 5000;

struct LossesInLog {
  std::map<std::string, std::int64_t> lost;         // by channel, by its seq
  std::map<std::string, std::int64_t> unexplained;  // of those, where the stream was not backed up
  std::int64_t backed_up = 0;                       // messages received kStallUs or more after their stamp
  std::int64_t messages = 0;

  // Losses where the stream flowed that a channel of `channel_messages` may
  // have as the machine's: as large a share as the run's messages that came
  // backed up. A machine starved of CPU drops packets in its network stack
  // too, unseen in any stamp, about as often as it lets a stream back up;
  // a link that loses packets on a machine that keeps up loses far more.
  std::int64_t UnexplainedAllowed(std::int64_t channel_messages) const {
    if (messages == 0 || backed_up == 0) return 0;
    return (channel_messages * backed_up + messages - 1) / messages;
  }
};

// Over `channels` (edsp's own, whose header carries utime and seq). A loss
// is the machine's when the message after it was received kStallUs or more
// after it was stamped (it waited in a full socket, or was a stalled
// publisher's catch-up burst), or after a silence of the whole log that
// long; on a link that loses packets the next one comes on time.
inline LossesInLog LossesExplainedByStalls(const std::string& log_path, const std::set<std::string>& channels) {
  std::map<std::string, std::int64_t> last_seq;
  LossesInLog out;
  LogReader reader(log_path);
  LogEvent event;
  std::int64_t last_receipt = -1;
  while (reader.Next(&event)) {
    const std::int64_t t = event.timestamp_utime;
    const bool after_silence = last_receipt >= 0 && t - last_receipt >= kStallUs;
    last_receipt = t;
    EdspHeader header;
    if (!channels.count(event.channel) || !ParseEdspHeader(event.data, &header)) continue;
    const bool late = t - header.utime >= kStallUs;
    out.messages += 1;
    out.backed_up += late ? 1 : 0;
    const auto [it, fresh] = last_seq.emplace(event.channel, header.seq);
    if (fresh) continue;
    const std::int64_t lost = SeqGap(it->second, header.seq);
    it->second = header.seq;
    if (lost == 0) continue;
    out.lost[event.channel] += lost;
    if (!late && !after_silence) out.unexplained[event.channel] += lost;
  }
  return out;
}

}  // namespace edsp::test_support
