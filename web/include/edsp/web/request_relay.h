#pragma once
// An operator's requests from the browser onto the group's bus, as edsp-ctl
// sends them: stamped by the server, not the client (the group's session,
// the operator's name "web:NAME" as client or operator_name, its own utime
// and seq), with the client's request_id (nonzero: the client finds its
// reply by it), and sent again every 0.5 s until its reply is on the board
// (EDSP_MOTION_REPLY or EDSP_REPLY) or 5 s pass: LCM is datagrams. What the
// request asks is for its node to check, as it checks edsp-ctl's.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "edsp/web/channel_board.h"
#include "edsp/web/request_json.h"

namespace edsp::web {

class RequestRelay {
 public:
  using Publish = std::function<bool(const std::string& channel, const RequestMessage& request)>;
  static constexpr std::int64_t kResendNs = 500'000'000;
  static constexpr std::int64_t kGiveUpNs = 5'000'000'000;

  // session_id <= 0: the group's, as its planner's EDSP_MOTION_STATUS says.
  RequestRelay(ChannelBoard* board, Publish publish, std::int64_t session_id);

  // Stamps and sends the request in `json_text` on `channel`; returns its
  // request_id. `owner`: whose it is (a connection), for ForgetOwner.
  // Throws foxglove::ProtocolError naming what is wrong: not a request
  // channel, a field (request_json.h), request_id 0 or one pending.
  std::int64_t Submit(std::string_view channel, std::string_view json_text, const std::string& operator_name,
                      std::int64_t now_ns, std::int64_t utime, std::uint64_t owner = 0);
  // Sends no more of what `owner` asked (its connection closed).
  void ForgetOwner(std::uint64_t owner);
  // Sends again what is due; forgets the answered and the given up.
  void Tick(std::int64_t now_ns);

  std::size_t pending() const { return pending_.size(); }
  std::int64_t sent() const { return sent_; }

 private:
  struct Pending {
    std::string channel;
    const char* reply_channel = nullptr;  // where its answer comes
    std::uint64_t owner = 0;
    RequestMessage request;
    std::int64_t next_send_ns = 0;
    std::int64_t give_up_ns = 0;
  };
  bool Send(Pending& p, std::int64_t now_ns);
  std::int64_t Session(const std::string& channel) const;
  void ForgetAnswered();

  ChannelBoard* board_;
  Publish publish_;
  std::int64_t session_id_;
  std::int64_t seq_ = 0;
  std::int64_t sent_ = 0;
  std::vector<Pending> pending_;
  std::uint64_t motion_replies_read_ = 0;
  std::uint64_t replies_read_ = 0;
};

}  // namespace edsp::web
