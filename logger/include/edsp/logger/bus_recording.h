#pragma once
// A running group's traffic recorded in memory from edsp's Bus, as a
// controller's data recorder (the Python package's Platform.record): every
// message of the channels asked for, on the routes the group gives them
// (LCM, or a shared-memory ring read whole), with the time it came, until
// stopped; then as columns (message_columns.h) or as an LCM log any edsp
// tool reads. Memory is bounded: beyond the bound, messages are counted and
// dropped, never the ones already kept.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "edsp/logger/log_reader.h"
#include "edsp/logger/message_columns.h"
#include "edsp/transport/bus.h"
#include "edsp/transport/transport_config.h"

namespace edsp {

struct BusRecordingStats {
  std::int64_t messages = 0;
  std::int64_t bytes = 0;
  std::int64_t dropped = 0;   // past max_bytes (of message bytes)
  std::int64_t overruns = 0;  // lost on a shared-memory ring (the recorder fell a ring behind)
  std::string error;          // the Bus failed while recording (what it said); "" if not
};

class BusRecording {
 public:
  // Subscribes to every channel whose whole name matches `channel_pattern`
  // (a POSIX extended regex) and records on a thread of its own. Throws
  // TransportError naming a bad pattern or a bus that cannot be opened.
  BusRecording(const TransportConfig& config, const std::string& channel_pattern, std::int64_t max_bytes);
  ~BusRecording();
  BusRecording(const BusRecording&) = delete;
  BusRecording& operator=(const BusRecording&) = delete;

  // Ends the recording (what came before is kept). Idempotent.
  void Stop();
  BusRecordingStats stats() const;

  // What was recorded so far, as tables per channel.
  MessageColumns Columns() const;
  // Writes it as an LCM log file (created anew). Throws std::runtime_error
  // naming the file if it cannot be written.
  void Save(const std::string& path) const;

 private:
  void Run();
  void Keep(const std::string& channel, const std::uint8_t* data, std::uint32_t size);

  std::unique_ptr<Bus> bus_;  // subscribed here, then handled by thread_ alone
  std::int64_t max_bytes_;
  mutable std::mutex mutex_;
  std::vector<LogEvent> events_;
  BusRecordingStats stats_;
  std::vector<std::string> shm_channels_;  // where overruns are counted
  std::atomic<bool> stopping_{false};
  std::once_flag stopped_;  // Stop() joins once, whoever calls it
  std::thread thread_;
};

}  // namespace edsp
