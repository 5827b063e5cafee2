#include "edsp/web/client_feed.h"

#include <cmath>

#include "edsp/web/foxglove_protocol.h"

namespace edsp::web {

ClientFeed::ClientFeed(ChannelBoard* board, double rate_cap_hz)
    : board_(board), interval_ns_(static_cast<std::int64_t>(std::llround(1e9 / rate_cap_hz))) {}

void ClientFeed::Subscribe(std::uint32_t subscription_id, std::uint32_t channel_id) {
  if (subscriptions_.count(subscription_id) != 0) {
    throw foxglove::ProtocolError("subscribe: subscription id " + std::to_string(subscription_id) + " is in use");
  }
  if (channel_id == 0 || channel_id > ChannelBoard::ChannelCount()) {
    throw foxglove::ProtocolError("subscribe: no channel " + std::to_string(channel_id) + " was advertised");
  }
  for (const auto& [id, other] : subscriptions_) {
    if (other.channel == channel_id - 1) {
      throw foxglove::ProtocolError("subscribe: channel " + std::to_string(channel_id) + " is subscribed already (id " +
                                    std::to_string(id) + ")");
    }
  }
  Cursor cursor;
  cursor.channel = channel_id - 1;
  if (ChannelBoard::KeepsEveryMessage(cursor.channel)) {
    // From now on: a new subscriber is not sent the history it subscribed after.
    std::uint64_t lost = 0;
    board_->Since(cursor.channel, &cursor.last_number, &lost);
  }
  subscriptions_.emplace(subscription_id, cursor);
}

void ClientFeed::Unsubscribe(std::uint32_t subscription_id) {
  if (subscriptions_.erase(subscription_id) == 0) {
    throw foxglove::ProtocolError("unsubscribe: no subscription " + std::to_string(subscription_id));
  }
}

std::vector<FeedFrame> ClientFeed::Due(std::int64_t now_ns, std::size_t max_frames) {
  std::vector<FeedFrame> frames;
  for (auto& [id, cursor] : subscriptions_) {
    if (frames.size() >= max_frames) break;
    if (ChannelBoard::KeepsEveryMessage(cursor.channel)) {
      for (BoardMessage& m : board_->Since(cursor.channel, &cursor.last_number, &lost_, max_frames - frames.size())) {
        frames.push_back(FeedFrame{id, m.receive_ns, std::move(m.json)});
      }
      continue;
    }
    if (now_ns < cursor.next_due_ns) continue;
    BoardMessage newest = board_->Latest(cursor.channel);
    if (newest.number == 0 || newest.number == cursor.last_number) continue;
    cursor.last_number = newest.number;
    // On the cap's schedule; a whole interval or more behind it (a stall, a
    // first frame), a new schedule from now: never a burst to catch up.
    cursor.next_due_ns += interval_ns_;
    if (cursor.next_due_ns <= now_ns) cursor.next_due_ns = now_ns + interval_ns_;
    frames.push_back(FeedFrame{id, newest.receive_ns, std::move(newest.json)});
  }
  return frames;
}

}  // namespace edsp::web
