#pragma once
// One LCM log file, written so that it always ends on a whole event, whatever
// happens to the writer: a full disk (a failed or short write is cut back to
// the last whole event and retried later), a kill mid-write (a restarted
// logger cuts the torn tail off and appends), an I/O error. lcm-logplayer and
// edsp-log then read every event that reached the disk.
//
// Events are encoded as LCM's log format (big-endian): sync word 0xEDA1DA01,
// event number (int64), timestamp (int64 µs), channel length (int32), data
// length (int32), channel, data.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace edsp {

struct LogResume {
  std::int64_t events = 0;      // whole events already in the file
  std::int64_t torn_bytes = 0;  // bytes of a torn last event, cut off
};

class LogFileAppender {
 public:
  // Opens `path`, creating it if needed. An existing log is resumed, never
  // truncated: a torn tail is cut and numbering continues. Returns nullptr
  // with *error naming the file and the reason if it cannot be opened, or if
  // the file is damaged before its tail (then nothing is written to it).
  static std::unique_ptr<LogFileAppender> Open(const std::string& path, LogResume* resume, std::string* error);
  ~LogFileAppender();
  LogFileAppender(const LogFileAppender&) = delete;
  LogFileAppender& operator=(const LogFileAppender&) = delete;

  // Encodes the event into the pending buffer (no I/O).
  void Append(const std::string& channel, const std::uint8_t* data, std::uint32_t size, std::int64_t utime);

  // Writes every pending event. Room is reserved first (fallocate), so on a
  // full disk only the whole events that fit are written and the file never
  // shows a torn event, even for an instant. On failure (ENOSPC, EFBIG, EIO,
  // a short write) the file ends on its last whole event (a partial write is
  // cut back), the events not written stay pending for the next Flush, and
  // *error says what failed.
  bool Flush(std::string* error);

  // Drops pending events from the newest back until at most `bytes` remain;
  // returns how many were dropped (a disk that stays full).
  std::int64_t DropPendingAbove(std::int64_t bytes);

  std::int64_t pending_bytes() const { return static_cast<std::int64_t>(pending_.size()); }
  std::int64_t pending_events() const { return static_cast<std::int64_t>(boundaries_.size()); }
  std::int64_t file_bytes() const { return committed_; }  // whole events on disk
  const std::string& path() const { return path_; }

 private:
  LogFileAppender(std::string path, int fd, std::int64_t committed, std::int64_t next_event);
  void KeepPendingFrom(std::size_t written_bytes);
  std::size_t WholeEventsWithin(std::int64_t bytes) const;  // bytes of pending_'s whole events within
  std::size_t BytesWithRoom(int* failure) const;            // of pending_, with disk room reserved

  std::string path_;
  int fd_ = -1;
  std::int64_t committed_ = 0;  // file size = end of the last whole event
  std::int64_t next_event_ = 0;
  std::vector<std::uint8_t> pending_;    // encoded events not yet on disk
  std::vector<std::size_t> boundaries_;  // end offset in pending_ of each event
};

}  // namespace edsp
