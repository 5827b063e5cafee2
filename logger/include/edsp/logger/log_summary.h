#pragma once
// What a log holds, per channel: counts, span, rate, and messages lost by
// their `seq` numbers (edsp's own channels).

#include <cstdint>
#include <map>
#include <string>

#include "edsp/logger/log_reader.h"

namespace edsp {

struct ChannelSummary {
  std::int64_t messages = 0;
  std::int64_t bytes = 0;
  std::int64_t first_utime = 0;
  std::int64_t last_utime = 0;
  std::int64_t seq_gaps = 0;      // messages missing between consecutive seq (0 on shared channels)
  std::int64_t seq_restarts = 0;  // seq going backwards (a publisher restarted)
  std::int64_t last_seq = -1;
  double rate_hz() const;
};

struct LogSummary {
  std::map<std::string, ChannelSummary> channels;
  std::int64_t events = 0;
  bool damaged = false;
  std::int64_t damage_offset = -1;
};

// Reads the whole log (up to any damage). Throws if it cannot be opened.
LogSummary SummarizeLog(const std::string& path);

}  // namespace edsp
