#pragma once
// How a node answers every request a client sends it (EDSP_ARM,
// EDSP_PR_MODE, EDSP_CALIBRATION on EDSP_REPLY; EDSP_MOTION_REQUEST on
// EDSP_MOTION_REPLY). A request and its reply are single UDP datagrams
// among the group's kHz traffic and either can be lost, so a client sends
// the same request (same request_id) again until it hears the reply; the
// node acts on a request_id once and answers every copy with the reply it
// gave. Before anything is acted on, the request must be this group's
// (session), stamped within the window of the node's clock (a log replayed
// later moves nothing; a sender whose clock is off is told so) and carry an
// id. For a switch (a mode, a calibration) a request stamped before the
// last one acted on is refused: a late copy must not undo a later command.
// Replies carry a typed code (reply_codes.h) beside the human reason.

#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "edsp/reply_codes.h"

namespace edsp {

struct RequestPolicy {
  std::int64_t session_id = 0;
  double window_s = 5.0;                 // a request stamped further from the node's clock is stale
  bool refuse_older_than_acted = false;  // a switch: nothing stamped before the last one acted on
};

// Why a request is not for this node now (code kDone: it is).
struct Refusal {
  ReplyCode code = ReplyCode::kDone;
  std::string reason;
};

// The checks before a request is looked at: session, stamp, id. `acted_utime`
// is the stamp of the last request acted on (policy.refuse_older_than_acted),
// or the lowest int64 when none was. Stamps are the sender's word: any int64
// is compared without overflow.
Refusal AddressProblem(const RequestPolicy& policy, std::int64_t session_id, std::int64_t request_id,
                       std::int64_t utime, std::int64_t now_utime, std::int64_t acted_utime);

template <typename Reply>
class RequestService {
 public:
  // Replies are kept twice as long as a copy can still be taken (clients
  // stamp a request once: a copy older than the window is stale), and at
  // most this many (a client flooding new ids cannot grow the node without
  // bound). The clock is the node's, or a replay's stamps: any int64.
  static constexpr std::size_t kRepliesMost = 100000;

  explicit RequestService(RequestPolicy policy) : policy_(std::move(policy)) {}
  const RequestPolicy& policy() const { return policy_; }

  struct Answer {
    Reply reply;
    bool acted = false;  // a new request, acted on (or refused on its merits) now
  };

  // `make(code, reason)` builds the reply's own fields (kind, node, channel);
  // `act()` acts on a new request and returns its reply. Every reply leaves
  // stamped: now, the next seq, the node's session, the request's id.
  template <typename Request, typename Make, typename Act>
  Answer Handle(const Request& request, std::int64_t now_utime, Make make, Act act) {
    Refusal problem =
        AddressProblem(policy_, request.session_id, request.request_id, request.utime, now_utime, acted_utime_);
    // Another group's or without an id: refused before the cache is looked
    // at. A copy of one answered gets its reply even when it came late.
    if (problem.code != ReplyCode::kDone && problem.code != ReplyCode::kStale) {
      return {Stamped(make(problem.code, std::move(problem.reason)), request.request_id, now_utime), false};
    }
    if (const auto it = replies_.find(request.request_id); it != replies_.end()) return {it->second, false};
    if (problem.code != ReplyCode::kDone) {
      return {Stamped(make(problem.code, std::move(problem.reason)), request.request_id, now_utime), false};
    }
    // The caller may act without its lock (a motion's path is checked so):
    // a copy answered meanwhile keeps its reply.
    Reply reply = act();
    if (const auto it = replies_.find(request.request_id); it != replies_.end()) return {it->second, false};
    reply = Stamped(std::move(reply), request.request_id, now_utime);
    if (reply.code == static_cast<std::int8_t>(ReplyCode::kDone) && policy_.refuse_older_than_acted) {
      acted_utime_ = std::max(acted_utime_, request.utime);
    }
    Remember(request.request_id, reply, now_utime);
    return {reply, true};
  }

 private:
  Reply Stamped(Reply reply, std::int64_t request_id, std::int64_t now_utime) {
    reply.utime = now_utime;
    reply.seq = ++seq_;
    reply.session_id = policy_.session_id;
    reply.request_id = request_id;
    return reply;
  }

  void Remember(std::int64_t request_id, const Reply& reply, std::int64_t now_utime) {
    replies_[request_id] = reply;
    order_.emplace_back(now_utime, request_id);
    const double keep_s = 2.0 * policy_.window_s;
    while (!order_.empty() &&
           (order_.size() > kRepliesMost ||
            (static_cast<double>(now_utime) - static_cast<double>(order_.front().first)) * 1e-6 > keep_s)) {
      replies_.erase(order_.front().second);
      order_.pop_front();
    }
  }

  RequestPolicy policy_;
  std::map<std::int64_t, Reply> replies_;                    // by request_id: every copy gets the same reply
  std::deque<std::pair<std::int64_t, std::int64_t>> order_;  // (utime answered, request_id)
  std::int64_t seq_ = 0;
  std::int64_t acted_utime_ = std::numeric_limits<std::int64_t>::min();
};

}  // namespace edsp
