#pragma once
// Writes LCM log files on a thread of its own, so a disk that stalls (write-
// back, a slow card, a full disk) never stalls the network receive: events
// queue in memory up to a bound, and only beyond it are dropped, counted.
// Rotates by size; flushes on a timer so a crash loses at most one interval.
// A full disk keeps the events in memory and retries every flush interval;
// the file always ends on a whole event (log_file_appender.h). An existing
// file is resumed, never truncated (a restarted logger appends).

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "edsp/logger/log_file_appender.h"

namespace edsp {

struct LogWriterOptions {
  std::string output = ".";       // a directory (timestamped names) or a file
  std::int64_t rotate_bytes = 0;  // 0: never
  int flush_ms = 200;
  std::int64_t max_queue_bytes = 256 << 20;  // in memory, queued or waiting for the disk
};

struct LogWriterStats {
  std::int64_t written = 0;
  std::int64_t dropped = 0;         // memory bound reached (disk too slow or full)
  std::int64_t write_errors = 0;    // flushes the disk refused (full?)
  std::int64_t recoveries = 0;      // flushes that succeeded after refused ones
  bool disk_failing = false;        // the last flush was refused
  std::int64_t waiting_events = 0;  // encoded, waiting for the disk
  std::int64_t resumed_events = 0;  // already in the first file when it was opened
  std::int64_t torn_bytes_cut = 0;  // of a torn last event in that file
  std::string path;                 // current file
  std::string last_error;
};

class LogWriter {
 public:
  // Creates the first file; throws std::runtime_error naming it on failure.
  explicit LogWriter(LogWriterOptions options);
  ~LogWriter();  // drains the queue, flushes, closes
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  // Never blocks on the disk. False if the event was dropped (queue full).
  bool Enqueue(const std::string& channel, const std::uint8_t* data, std::uint32_t size, std::int64_t utime);
  LogWriterStats stats() const;

 private:
  struct Event {
    std::string channel;
    std::vector<std::uint8_t> data;
    std::int64_t utime;
  };
  void Run();
  void OpenPart();
  void WriteOne(const Event& event);
  void FlushFile();

  LogWriterOptions options_;
  std::string stamp_;
  int part_ = 0;
  std::unique_ptr<LogFileAppender> file_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Event> queue_;
  std::int64_t queued_bytes_ = 0;
  std::int64_t waiting_bytes_ = 0;  // encoded in file_, not yet on disk
  bool stopping_ = false;
  LogWriterStats stats_;
  std::thread thread_;
};

// <dir>/edsp-<stamp>.NN.lcmlog for a directory; the file itself for part 0
// of a file, and <name>.NN.<ext> for later parts.
std::string LogPartPath(const std::string& output, const std::string& stamp, int part);

}  // namespace edsp
