#include "edsp/web/channel_board.h"

#include <iterator>

#include "edsp/channels.h"
#include "edsp/web/message_json.h"

namespace edsp::web {
namespace {

// The message as JSON text, or null if the bytes do not decode as an edsp
// type. Text that is not UTF-8 (a node's reason, an operator's name) is
// sent with U+FFFD where it breaks, not refused.
std::shared_ptr<const std::string> JsonText(const std::string& bytes) {
  nlohmann::ordered_json message;
  if (!MessageToJson(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &message)) return nullptr;
  return std::make_shared<const std::string>(
      message.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
}

}  // namespace

ChannelBoard::ChannelBoard(std::size_t event_capacity)
    : event_capacity_(event_capacity == 0 ? 1 : event_capacity), slots_(ChannelCount()) {}

std::size_t ChannelBoard::ChannelCount() { return std::size(channel::kChannels); }

std::size_t ChannelBoard::IndexOf(std::string_view name) {
  for (std::size_t i = 0; i < ChannelCount(); ++i) {
    if (channel::kChannels[i].name == name) return i;
  }
  return ChannelCount();
}

bool ChannelBoard::KeepsEveryMessage(std::size_t channel) {
  return channel < ChannelCount() && channel::kChannels[channel].rate_hz == 0.0;
}

void ChannelBoard::Post(std::string_view channel, std::int64_t receive_ns, const std::uint8_t* data, std::size_t size) {
  const std::size_t index = IndexOf(channel);
  if (index == ChannelCount()) return;
  if (KeepsEveryMessage(index)) {
    // Rare (on event): made JSON here, once, so that readers share it.
    std::shared_ptr<const std::string> text = JsonText(std::string(reinterpret_cast<const char*>(data), size));
    const std::lock_guard<std::mutex> lock(mutex_);
    if (text == nullptr) {
      ++undecodable_;
      return;
    }
    Slot& slot = slots_[index];
    slot.events.push_back(BoardMessage{++slot.number, receive_ns, std::move(text)});
    if (slot.events.size() > event_capacity_) slot.events.pop_front();
    return;
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  Slot& slot = slots_[index];
  ++slot.number;
  slot.receive_ns = receive_ns;
  slot.bytes.assign(reinterpret_cast<const char*>(data), size);  // its capacity kept: no allocation per message
}

BoardMessage ChannelBoard::Latest(std::size_t channel) {
  if (channel >= ChannelCount() || KeepsEveryMessage(channel)) return {};
  std::string bytes;
  BoardMessage newest;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const Slot& slot = slots_[channel];
    if (slot.number == 0) return {};
    newest.number = slot.number;
    newest.receive_ns = slot.receive_ns;
    if (slot.json_number == slot.number) {
      if (slot.json == nullptr) return {};  // it did not decode: counted once, never sent
      newest.json = slot.json;
      return newest;
    }
    bytes = slot.bytes;
  }
  newest.json = JsonText(bytes);  // outside the lock: the bus thread does not wait for it
  const std::lock_guard<std::mutex> lock(mutex_);
  Slot& slot = slots_[channel];
  if (newest.json == nullptr) {
    if (slot.json_number != newest.number) ++undecodable_;
    slot.json_number = newest.number;
    slot.json = nullptr;
    return {};
  }
  if (slot.number == newest.number) {
    slot.json_number = newest.number;
    slot.json = newest.json;
  }
  return newest;
}

std::vector<BoardMessage> ChannelBoard::Since(std::size_t channel, std::uint64_t* after, std::uint64_t* lost,
                                              std::size_t max_count) {
  std::vector<BoardMessage> out;
  if (!KeepsEveryMessage(channel)) return out;
  const std::lock_guard<std::mutex> lock(mutex_);
  const Slot& slot = slots_[channel];
  if (slot.events.empty() || slot.events.back().number <= *after) return out;
  const std::uint64_t first = slot.events.front().number;
  if (first > *after + 1) {
    *lost += first - (*after + 1);
    *after = first - 1;
  }
  for (const BoardMessage& m : slot.events) {
    if (out.size() == max_count) break;
    if (m.number > *after) out.push_back(m);
  }
  if (!out.empty()) *after = out.back().number;
  return out;
}

std::uint64_t ChannelBoard::posted() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::uint64_t n = 0;
  for (const Slot& slot : slots_) n += slot.number;
  return n;
}

std::uint64_t ChannelBoard::undecodable() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return undecodable_;
}

}  // namespace edsp::web
