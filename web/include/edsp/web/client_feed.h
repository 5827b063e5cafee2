#pragma once
// One client's subscriptions and what is due to it, apart from any socket:
// the server asks Due() whenever the client's socket can take more, so a
// slow client only ever gets fewer, newer frames, and the memory it holds
// is its subscriptions' cursors.
//  - a latest-wins channel: its newest message, if newer than the last one
//    sent and the rate cap's interval has passed since (the cap's schedule
//    keeps its average rate, a late tick does not lower it);
//  - an every-message channel (faults, replies): every message since the
//    last call, in order; what the board overwrote meanwhile is counted.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "edsp/web/channel_board.h"

namespace edsp::web {

struct FeedFrame {
  std::uint32_t subscription_id = 0;
  std::int64_t receive_ns = 0;
  std::shared_ptr<const std::string> json;
};

class ClientFeed {
 public:
  // rate_cap_hz > 0: the most frames per second of one latest-wins channel.
  ClientFeed(ChannelBoard* board, double rate_cap_hz);

  // channel_id: the board's row + 1, as advertised. Throws
  // foxglove::ProtocolError naming an id in use, a channel not advertised
  // or one this client already subscribed (the protocol allows one each).
  void Subscribe(std::uint32_t subscription_id, std::uint32_t channel_id);
  // Throws foxglove::ProtocolError naming an id not subscribed.
  void Unsubscribe(std::uint32_t subscription_id);

  // At most `max_frames`: an event channel's rest waits for the next call.
  std::vector<FeedFrame> Due(std::int64_t now_ns, std::size_t max_frames);

  // Every-message channels' messages overwritten before this client read them.
  std::uint64_t lost() const { return lost_; }
  std::size_t subscriptions() const { return subscriptions_.size(); }

 private:
  struct Cursor {
    std::size_t channel = 0;
    std::uint64_t last_number = 0;  // the last message sent (latest-wins) or read (every-message)
    std::int64_t next_due_ns = 0;
  };

  ChannelBoard* board_;
  std::int64_t interval_ns_;
  std::map<std::uint32_t, Cursor> subscriptions_;
  std::uint64_t lost_ = 0;
};

}  // namespace edsp::web
