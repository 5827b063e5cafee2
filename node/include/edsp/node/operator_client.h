#pragma once
// An operator's request (EDSP_ARM, EDSP_PR_MODE, EDSP_CALIBRATION) sent as
// a client must: again every 0.5 s until the node answers on EDSP_FAULT
// about that channel, or the timeout (operator_requests.h: the node acts on
// it once and answers every copy alike). edsp-ctl and the Python Platform
// both send theirs through this.

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

struct OperatorAnswer {
  bool given = false;      // the node answered within the timeout
  bool confirmed = false;  // it acted (code operator_action), else it refused
  std::string reason;      // its words
};

// Stamps `request` (utime, seq 1; session and operator are the caller's),
// sends it on `channel` until `node` answers or `timeout_s` passes. The
// bus's subscription stays for its life (Bus has no unsubscribe).
template <typename Msg>
OperatorAnswer SendOperatorRequest(Bus& bus, const std::string& channel, Msg request, const std::string& node,
                                   double timeout_s) {
  using Clock = std::chrono::steady_clock;
  constexpr auto kResend = std::chrono::milliseconds(500);
  auto answer = std::make_shared<OperatorAnswer>();
  bus.Subscribe<fault_t>(channel::kFault, [answer, node, channel](const fault_t& f) {
    if (answer->given || f.node != node || f.channel != channel) return;
    answer->given = true;
    answer->confirmed = f.code == static_cast<std::int32_t>(FaultCode::kOperatorAction);
    answer->reason = f.reason;
  });
  request.utime = UtimeNow();
  request.seq = 1;
  const auto until =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  auto next_send = Clock::now();
  while (!answer->given && Clock::now() < until) {
    if (Clock::now() >= next_send) {
      if (!bus.Publish(channel, request)) throw std::runtime_error(channel + " could not be sent");
      next_send = Clock::now() + kResend;
    }
    bus.Handle(std::chrono::milliseconds(50));
  }
  return *answer;
}

}  // namespace edsp
