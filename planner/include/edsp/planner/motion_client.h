#pragma once
// A client of a running group over edsp's Bus: what edsp-ctl and the
// Python Platform share. It finds the group's session (unless told), sends
// the planner's motion requests and the operator's (arm, PR mode,
// calibration) as every request is sent (node/request_client.h), follows
// EDSP_MOTION_STATUS, and waits for a motion to end: on target, halted or
// stopped, a fault, or the timeout.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "edsp/channels.h"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/request_client.h"
#include "edsp/reply_t.hpp"
#include "edsp/transport/bus.h"

namespace edsp {

const char* MotionStateName(std::int8_t state);  // "idle", "moving", ...
const char* MotionEndName(std::int8_t end);      // "none", "completed", "halted", "stopped"

enum class WaitOutcome { kOnTarget, kHaltedOrStopped, kFault, kTimedOut };

struct WaitResult {
  WaitOutcome outcome = WaitOutcome::kTimedOut;
  std::string message;                    // why, for anything but on target
  std::optional<motion_status_t> status;  // the last one seen
};

class MotionClient {
 public:
  // Throws std::runtime_error if the session cannot be found (none or
  // several groups on the bus within answer_timeout_s).
  MotionClient(const TransportConfig& transport, std::optional<std::int64_t> session_id, double answer_timeout_s,
               std::string client_name);
  // Its bus's handlers and its request client point into it.
  MotionClient(const MotionClient&) = delete;
  MotionClient& operator=(const MotionClient&) = delete;

  std::int64_t session_id() const { return session_; }
  const std::string& client_name() const { return client_; }
  double answer_timeout_s() const { return answer_timeout_s_; }
  // A request of `kind` with a fresh random request_id, this session and client.
  motion_request_t Request(std::int8_t kind) const;
  // Sends `request` until its reply comes or the answer timeout passes (none).
  std::optional<motion_reply_t> Send(motion_request_t request);
  // An operator's request (arm_t, pr_mode_t, calibration_t: its own fields
  // filled) on `channel`, with a fresh id, this session and client as the
  // operator, until its node's reply on EDSP_REPLY or the answer timeout.
  template <typename Msg>
  std::optional<reply_t> SendOperator(const std::string& channel, Msg request) {
    request.session_id = session_;
    request.request_id = RequestClient::NewRequestId();
    request.operator_name = client_;
    return requests_.Send<reply_t>(channel, channel::kReply, request, answer_timeout_s_);
  }
  // The next status of this session published after now (older ones
  // waiting in the socket are dropped), within `seconds`.
  std::optional<motion_status_t> NextStatus(double seconds);
  // Until motion `request_id` (0: whatever runs now) is on target, ends
  // halted or stopped, the bridge faults, or `timeout_s` passes. A wait in
  // slices (to answer Ctrl-C between them) passes the same `seen` to each.
  WaitResult Wait(std::int64_t request_id, double timeout_s);
  WaitResult Wait(std::int64_t request_id, double timeout_s, bool* seen);

 private:
  struct Inbox {
    std::optional<motion_status_t> status;
  };
  Bus bus_;
  RequestClient requests_{bus_};
  std::int64_t session_;
  double answer_timeout_s_;
  std::string client_;
  std::shared_ptr<Inbox> inbox_ = std::make_shared<Inbox>();
};

}  // namespace edsp
