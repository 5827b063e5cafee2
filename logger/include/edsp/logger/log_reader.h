#pragma once
// Reading standard LCM log files (what lcm-logger, edsp-logger and
// lcm-logplayer use), up to the first damage, saying where it is: every
// whole event before the damage is read.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace edsp {

struct LogEvent {
  std::int64_t event_number = 0;
  std::int64_t timestamp_utime = 0;  // when the logger received it
  std::string channel;
  std::vector<std::uint8_t> data;
};

// Every edsp message starts with the LCM fingerprint, then utime and seq.
struct EdspHeader {
  std::int64_t fingerprint = 0;
  std::int64_t utime = 0;
  std::int64_t seq = 0;
};
bool ParseEdspHeader(const std::uint8_t* data, std::size_t size, EdspHeader* header);
bool ParseEdspHeader(const std::vector<std::uint8_t>& data, EdspHeader* header);

class LogReader {
 public:
  // Throws std::runtime_error naming the file if it cannot be opened.
  explicit LogReader(const std::string& path);
  ~LogReader();
  // False at the end of the log, or at damage (then damaged() is true).
  bool Next(LogEvent* event);
  bool damaged() const { return damaged_; }
  std::int64_t damage_offset() const { return damage_offset_; }  // bytes into the file
  std::int64_t file_size() const { return file_size_; }

 private:
  bool ReadEventAt(LogEvent* event);  // the event at whole_bytes_, if whole

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::int64_t whole_bytes_ = 0;  // the log up to here is whole events
  bool damaged_ = false;
  std::int64_t damage_offset_ = -1;
  std::int64_t file_size_ = 0;
};

}  // namespace edsp
