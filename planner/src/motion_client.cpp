#include "edsp/planner/motion_client.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "edsp/channels.h"
#include "edsp/node/runtime.h"
#include "edsp/node/session_discovery.h"

namespace edsp {

namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point Deadline(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

}  // namespace

const char* MotionStateName(std::int8_t state) {
  switch (state) {
    case motion_status_t::STATE_IDLE: return "idle";
    case motion_status_t::STATE_MOVING: return "moving";
    case motion_status_t::STATE_HALTING: return "halting";
    case motion_status_t::STATE_HOLDING: return "holding";
    case motion_status_t::STATE_REFUSED: return "refused";
    case motion_status_t::STATE_FAULT: return "fault";
    case motion_status_t::STATE_CUEING: return "cueing";
  }
  return "unknown";
}

const char* MotionEndName(std::int8_t end) {
  switch (end) {
    case motion_status_t::END_COMPLETED: return "completed";
    case motion_status_t::END_HALTED: return "halted";
    case motion_status_t::END_STOPPED: return "stopped";
  }
  return "none";
}

MotionClient::MotionClient(const TransportConfig& transport, std::optional<std::int64_t> session_id,
                           double answer_timeout_s, std::string client_name)
    : bus_(transport),
      session_(session_id ? *session_id : DiscoverSession(bus_, answer_timeout_s)),
      answer_timeout_s_(answer_timeout_s),
      client_(std::move(client_name)) {
  bus_.Subscribe<motion_status_t>(channel::kMotionStatus,
                                  [inbox = inbox_, session = session_](const motion_status_t& s) {
                                    if (s.session_id == session) inbox->status = s;
                                  });
}

motion_request_t MotionClient::Request(std::int8_t kind) const {
  motion_request_t r{};
  r.session_id = session_;
  r.request_id = RequestClient::NewRequestId();
  r.client = client_;
  r.kind = kind;
  return r;
}

std::optional<motion_reply_t> MotionClient::Send(motion_request_t r) {
  return requests_.Send<motion_reply_t>(channel::kMotionRequest, channel::kMotionReply, r, answer_timeout_s_);
}

std::optional<motion_status_t> MotionClient::NextStatus(double seconds) {
  while (bus_.Handle(std::chrono::milliseconds(0)) > 0) {
  }
  inbox_->status.reset();
  const auto until = Deadline(seconds);
  while (!inbox_->status && Clock::now() < until) bus_.Handle(std::chrono::milliseconds(20));
  return inbox_->status;
}

WaitResult MotionClient::Wait(std::int64_t request_id, double timeout_s) {
  bool seen = false;
  return Wait(request_id, timeout_s, &seen);
}

WaitResult MotionClient::Wait(std::int64_t request_id, double timeout_s, bool* seen_before) {
  WaitResult result;
  const auto until = Deadline(timeout_s);
  // A status from before the motion started (still naming the one before)
  // says nothing about it: only once it is named is its end awaited.
  bool& seen = *seen_before;
  seen = seen || request_id == 0;
  while (Clock::now() < until) {
    const std::optional<motion_status_t> s = NextStatus(std::min(1.0, std::max(0.05, timeout_s)));
    if (!s) continue;
    result.status = s;
    seen = seen || s->request_id == request_id;
    if (s->state == motion_status_t::STATE_FAULT) {
      result.outcome = WaitOutcome::kFault;
      result.message = s->reason;
      return result;
    }
    const bool still = s->state != motion_status_t::STATE_MOVING && s->state != motion_status_t::STATE_HALTING;
    const bool halted = s->last_end == motion_status_t::END_HALTED || s->last_end == motion_status_t::END_STOPPED;
    if (!seen && still && s->queued == 0 && halted) {
      // Never started and nothing waits: a halt or stop cancelled it in the queue.
      result.outcome = WaitOutcome::kHaltedOrStopped;
      result.message = std::string("the motion was cancelled before it started (") + MotionEndName(s->last_end) + ")";
      return result;
    }
    if (!seen || !still) continue;
    if (halted) {
      result.outcome = WaitOutcome::kHaltedOrStopped;
      result.message = std::string("the motion was ") + MotionEndName(s->last_end);
      return result;
    }
    if (s->on_target) {
      result.outcome = WaitOutcome::kOnTarget;
      return result;
    }
  }
  result.outcome = WaitOutcome::kTimedOut;
  result.message = "not on target within " + std::to_string(timeout_s) + " s";
  return result;
}

}  // namespace edsp
