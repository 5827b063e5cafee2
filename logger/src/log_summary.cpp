#include "edsp/logger/log_summary.h"

#include "edsp/channels.h"
#include "edsp/transport/seq_gap.h"

namespace edsp {

double ChannelSummary::rate_hz() const {
  const double span = static_cast<double>(last_utime - first_utime) * 1e-6;
  return messages > 1 && span > 0.0 ? static_cast<double>(messages - 1) / span : 0.0;
}

LogSummary SummarizeLog(const std::string& path) {
  LogReader reader(path);
  LogSummary summary;
  LogEvent event;
  while (reader.Next(&event)) {
    ++summary.events;
    ChannelSummary& c = summary.channels[event.channel];
    if (c.messages == 0) c.first_utime = event.timestamp_utime;
    ++c.messages;
    c.bytes += static_cast<std::int64_t>(event.data.size());
    c.last_utime = event.timestamp_utime;
    EdspHeader header;
    if (event.channel.rfind("EDSP_", 0) == 0 && !channel::SeqGapsAreNotLosses(event.channel) &&
        ParseEdspHeader(event.data, &header)) {
      c.seq_gaps += SeqGap(c.last_seq, header.seq);
      if (c.last_seq >= 0 && header.seq <= c.last_seq) ++c.seq_restarts;
      c.last_seq = header.seq;
    }
  }
  summary.damaged = reader.damaged();
  summary.damage_offset = reader.damage_offset();
  return summary;
}

}  // namespace edsp
