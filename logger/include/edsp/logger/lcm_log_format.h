#pragma once
// The LCM log file format, as lcm-logger writes it and lcm-logplayer reads
// it: each event is a 28-byte big-endian header (sync word, event number,
// timestamp, channel length, data length), the channel name, then the data.
// One place for the layout, shared by the reader and the appender.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace edsp {
namespace lcm_log {

constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;
// LCM's own reader refuses channel names of 1000 bytes or more.
constexpr std::int32_t kMaxChannelBytes = 999;

struct EventHeader {
  std::int64_t event_number = 0;
  std::int64_t timestamp_utime = 0;
  std::int32_t channel_bytes = 0;
  std::int32_t data_bytes = 0;
  std::int64_t total_bytes() const { return static_cast<std::int64_t>(kHeaderBytes) + channel_bytes + data_bytes; }
};

// A plausible header at `p` (kHeaderBytes long) for an event that must fit
// in the `room` bytes left in the file.
bool ParseEventHeader(const std::uint8_t* p, std::int64_t room, EventHeader* header);

// Appends the header of an event (the caller appends channel and data).
void AppendEventHeader(std::vector<std::uint8_t>* out, std::int64_t event_number, std::int64_t utime,
                       std::size_t channel_bytes, std::uint32_t data_bytes);

// Inline: read_log takes every event's header at hundreds of MB/s.
inline std::uint64_t GetBigEndian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) v = (v << 8) | p[k];
  return v;
}

}  // namespace lcm_log
}  // namespace edsp
