#pragma once
// The edsp-logger node: records the channels matching a pattern to LCM log
// files (LogWriter), taking each through the Bus (a channel this host reads
// on shared memory, whole, from there; the rest from LCM), counts what each
// channel lost by its `seq` numbers, and reports the disk's health and its
// status. edsp-logger's main only parses options and runs one.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "edsp/fault_t.hpp"
#include "edsp/logger/disk_health.h"
#include "edsp/logger/log_writer.h"
#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "edsp/transport/bus.h"
#include "edsp/transport/seq_gap.h"

namespace edsp {

struct LoggerOptions {
  std::string channels = "EDSP_.*";  // POSIX extended regex, whole channel name
  LogWriterOptions writer;
};

class LoggerNode {
 public:
  // Opens (or resumes) the log and subscribes; reports on EDSP_FAULT what it
  // found in a resumed file. Throws if the log cannot be opened or the
  // pattern is no regex. `bus` outlives the node and is not handled once the
  // node is gone (the Bus keeps its handler).
  LoggerNode(Bus& bus, LoggerOptions options);

  // Looks at the disk (an episode is reported at once) and at the rings it
  // cannot read (each new reason once, a warning: the channel's LCM copy is
  // recorded meanwhile), and publishes the status when due. Call at least
  // every 20 ms.
  void Poll(std::int64_t now);
  // Handles the bus and polls until `stop` says so; the writer then drains.
  void Run(const std::function<bool()>& stop);

  // Messages lost before they reached the logger: LCM's by the gaps in
  // each channel's `seq`, shared memory's as the ring's own count of what a
  // lagging read missed (exact, even before the first message read).
  std::int64_t lost() const;
  const std::vector<std::string>& shm_channels() const { return shm_channels_; }
  LogWriterStats writer_stats() const { return writer_.stats(); }

 private:
  void Record(const std::string& channel, const std::uint8_t* data, std::uint32_t size);
  void ReportOpened();
  void ReportUnreadableRings(std::int64_t now);
  bool IsOnSharedMemory(const std::string& channel) const;

  Bus& bus_;
  LogWriter writer_;
  NodeReporting reporting_;
  DiskHealth disk_;
  std::map<std::string, SeqTracker> seqs_;  // LCM channels with one publisher
  std::int64_t lcm_seq_gaps_ = 0;
  std::vector<std::string> shm_channels_;
  std::map<std::string, std::string> reported_ring_errors_;
};

}  // namespace edsp
