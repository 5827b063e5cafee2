#pragma once
// What the group sends, as edsp-web's clients see it. Per channel of the
// channel table (channels.h; a channel's id is its row + 1):
//  - latest-wins channels (those with a nominal rate): the newest message
//    only; a client at 30 Hz gets the newest of the thirty-odd a 1 kHz
//    channel sent since its last frame, never a backlog;
//  - every-message channels (faults, replies, requests: the table's
//    on-event rows): the last `event_capacity` messages, numbered, so that
//    each client reads them in order from where it left off and counts
//    what was overwritten before it came back.
// Posted from the bus thread, read from the server's. The bus thread never
// waits on a client: Post copies the bytes under a short lock; a message's
// JSON is made once, by the first reader that wants it.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace edsp::web {

struct BoardMessage {
  std::uint64_t number = 0;  // 1, 2, ... per channel; 0: none yet
  std::int64_t receive_ns = 0;
  std::shared_ptr<const std::string> json;  // the message as JSON text (message_json.h)
};

class ChannelBoard {
 public:
  explicit ChannelBoard(std::size_t event_capacity = 1024);

  static std::size_t ChannelCount();
  // The row of `name` in the channel table, or ChannelCount() if it is not edsp's.
  static std::size_t IndexOf(std::string_view name);
  // Whether every message of the channel is kept (else the newest only).
  static bool KeepsEveryMessage(std::size_t channel);

  // From the bus thread. A channel that is not edsp's is ignored.
  void Post(std::string_view channel, std::int64_t receive_ns, const std::uint8_t* data, std::size_t size);

  // The newest message of a latest-wins channel (number 0 when none has
  // come, or when it did not decode: counted in undecodable()).
  BoardMessage Latest(std::size_t channel);
  // The messages of an every-message channel numbered after `*after`, in
  // order, at most `max_count`; advances `*after` past those returned and
  // adds to `*lost` those overwritten unread.
  std::vector<BoardMessage> Since(std::size_t channel, std::uint64_t* after, std::uint64_t* lost,
                                  std::size_t max_count = std::numeric_limits<std::size_t>::max());

  std::uint64_t undecodable() const;
  // Messages taken in so far, every channel (the node's messages_in).
  std::uint64_t posted() const;

 private:
  struct Slot {
    std::uint64_t number = 0;
    std::int64_t receive_ns = 0;
    std::string bytes;                        // latest-wins: the newest message's
    std::shared_ptr<const std::string> json;  // made from bytes for json_number
    std::uint64_t json_number = 0;
    std::deque<BoardMessage> events;  // every-message channels
  };

  std::size_t event_capacity_;
  mutable std::mutex mutex_;
  std::vector<Slot> slots_;
  std::uint64_t undecodable_ = 0;
};

}  // namespace edsp::web
