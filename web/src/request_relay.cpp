#include "edsp/web/request_relay.h"

#include <algorithm>
#include <set>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/web/foxglove_protocol.h"

namespace edsp::web {
namespace {

std::int64_t RequestIdOf(const RequestMessage& r) {
  return std::visit([](const auto& m) { return m.request_id; }, r);
}

// Who asks and in which session: the server's to say, never the client's.
void Stamp(RequestMessage& r, std::int64_t session_id, const std::string& operator_name) {
  std::visit(
      [&](auto& m) {
        m.session_id = session_id;
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, motion_request_t>) {
          m.client = operator_name;
        } else {
          m.operator_name = operator_name;
        }
      },
      r);
}

// The request ids of the replies the board got since `*after`.
void RepliedIds(ChannelBoard* board, const char* channel, std::uint64_t* after, std::set<std::int64_t>* ids) {
  std::uint64_t lost = 0;
  for (const BoardMessage& m : board->Since(ChannelBoard::IndexOf(channel), after, &lost)) {
    const auto reply = nlohmann::json::parse(*m.json, nullptr, false);
    if (reply.is_object() && reply.contains("request_id")) ids->insert(reply["request_id"].get<std::int64_t>());
  }
}

}  // namespace

RequestRelay::RequestRelay(ChannelBoard* board, Publish publish, std::int64_t session_id)
    : board_(board), publish_(std::move(publish)), session_id_(session_id) {
  std::set<std::int64_t> ignored;  // replies from before this relay answer nothing of its own
  RepliedIds(board_, channel::kMotionReply, &motion_replies_read_, &ignored);
  RepliedIds(board_, channel::kReply, &replies_read_, &ignored);
}

std::int64_t RequestRelay::Submit(std::string_view channel, std::string_view json_text,
                                  const std::string& operator_name, std::int64_t now_ns, std::int64_t utime,
                                  std::uint64_t owner) {
  Pending p;
  p.channel = std::string(channel);
  p.request = RequestFromJson(channel, json_text);
  p.reply_channel = p.channel == channel::kMotionRequest ? channel::kMotionReply : channel::kReply;
  p.owner = owner;
  p.next_send_ns = now_ns;
  p.give_up_ns = now_ns + kGiveUpNs;
  const std::int64_t id = RequestIdOf(p.request);
  if (id == 0) throw foxglove::ProtocolError(p.channel + ": request_id must be nonzero (the reply is found by it)");
  for (const Pending& other : pending_) {
    if (RequestIdOf(other.request) == id) {
      throw foxglove::ProtocolError(p.channel + ": request " + std::to_string(id) + " is still pending");
    }
  }
  Stamp(p.request, Session(p.channel), operator_name);
  std::visit([&](auto& m) { m.utime = utime; }, p.request);  // stamped once: its copies are as old as it
  if (!Send(p, now_ns)) throw foxglove::ProtocolError(p.channel + " could not be sent on the bus");
  pending_.push_back(std::move(p));
  return id;
}

std::int64_t RequestRelay::Session(const std::string& channel) const {
  if (session_id_ > 0) return session_id_;
  // Beside a running group: its session as its planner says it.
  const BoardMessage status = board_->Latest(ChannelBoard::IndexOf(channel::kMotionStatus));
  if (status.json != nullptr) {
    const auto parsed = nlohmann::json::parse(*status.json, nullptr, false);
    if (parsed.is_object() && parsed.contains("session_id") && parsed["session_id"].get<std::int64_t>() > 0) {
      return parsed["session_id"].get<std::int64_t>();
    }
  }
  throw foxglove::ProtocolError(channel +
                                ": the group's session is not known yet (no EDSP_MOTION_STATUS seen); "
                                "start edsp-web with --session-id or wait for the planner");
}

bool RequestRelay::Send(Pending& p, std::int64_t now_ns) {
  std::visit([&](auto& m) { m.seq = ++seq_; }, p.request);
  p.next_send_ns = now_ns + kResendNs;
  ++sent_;
  return publish_(p.channel, p.request);
}

void RequestRelay::ForgetAnswered() {
  // Answered on its own reply channel: a motion request by the planner, the
  // others by the node that took them.
  std::set<std::int64_t> motion_answered;
  std::set<std::int64_t> answered;
  RepliedIds(board_, channel::kMotionReply, &motion_replies_read_, &motion_answered);
  RepliedIds(board_, channel::kReply, &replies_read_, &answered);
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                [&](const Pending& p) {
                                  const auto& ids =
                                      p.reply_channel == channel::kMotionReply ? motion_answered : answered;
                                  return ids.count(RequestIdOf(p.request)) != 0;
                                }),
                 pending_.end());
}

void RequestRelay::ForgetOwner(std::uint64_t owner) {
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(), [&](const Pending& p) { return p.owner == owner; }),
                 pending_.end());
}

void RequestRelay::Tick(std::int64_t now_ns) {
  ForgetAnswered();
  pending_.erase(
      std::remove_if(pending_.begin(), pending_.end(), [&](const Pending& p) { return now_ns >= p.give_up_ns; }),
      pending_.end());
  for (Pending& p : pending_) {
    if (now_ns >= p.next_send_ns) Send(p, now_ns);
  }
}

}  // namespace edsp::web
