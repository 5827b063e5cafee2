#include "edsp/logger/lcm_log_format.h"

namespace edsp {
namespace lcm_log {

namespace {

void PutBigEndian(std::vector<std::uint8_t>* out, std::uint64_t value, int bytes) {
  for (int k = bytes - 1; k >= 0; --k) out->push_back(static_cast<std::uint8_t>(value >> (8 * k)));
}

}  // namespace

bool ParseEventHeader(const std::uint8_t* p, std::int64_t room, EventHeader* header) {
  if (GetBigEndian(p, 4) != kSyncWord) return false;
  const auto channel = static_cast<std::int32_t>(GetBigEndian(p + 20, 4));
  const auto data = static_cast<std::int32_t>(GetBigEndian(p + 24, 4));
  if (channel <= 0 || channel > kMaxChannelBytes || data < 0) return false;
  header->event_number = static_cast<std::int64_t>(GetBigEndian(p + 4, 8));
  header->timestamp_utime = static_cast<std::int64_t>(GetBigEndian(p + 12, 8));
  header->channel_bytes = channel;
  header->data_bytes = data;
  return header->total_bytes() <= room;
}

void AppendEventHeader(std::vector<std::uint8_t>* out, std::int64_t event_number, std::int64_t utime,
                       std::size_t channel_bytes, std::uint32_t data_bytes) {
  PutBigEndian(out, kSyncWord, 4);
  PutBigEndian(out, static_cast<std::uint64_t>(event_number), 8);
  PutBigEndian(out, static_cast<std::uint64_t>(utime), 8);
  PutBigEndian(out, channel_bytes, 4);
  PutBigEndian(out, data_bytes, 4);
}

}  // namespace lcm_log
}  // namespace edsp
