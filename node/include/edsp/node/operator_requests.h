#pragma once
// An operator's request (EDSP_ARM, EDSP_PR_MODE, EDSP_CALIBRATION) and the
// node's answer travel on LCM among the group's kHz traffic, and either can
// be lost. edsp-ctl therefore sends the same request again until it hears
// an answer. The node acts on a request once and answers each copy with the
// answer it gave (a re-arm is not repeated, the confirmation names the
// switch that was made), and never acts on a request older than the last
// one it acted on (a late copy must not undo a later operator's command).
// Only what was acted on is remembered: a refused request (another
// session's, a value the node cannot take) holds nothing back, and one
// stamped far in the future (a sender whose clock is off) is refused
// before it could hold back every request after it.

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "edsp/fault_t.hpp"
#include "edsp/node/fault.h"

namespace edsp {

class OperatorRequestAnswers {
 public:
  // A request stamped further ahead of the node's clock than this is refused.
  static constexpr double kMaxAhead_us = 10e6;

  // `act()` → fault_t for a new request, remembered when it acted (code
  // operator_action); the same answer for a copy of the one acted on (same
  // utime, seq and operator); `refuse(reason)` → fault_t for one older than
  // it or stamped in the future. The stamps are the sender's word: any
  // int64 is compared without overflow.
  template <typename Request, typename Act, typename Refuse>
  fault_t Answer(const Request& request, std::int64_t now_utime, Act act, Refuse refuse) {
    if (answered_ && request.utime == utime_ && request.seq == seq_ && request.operator_name == operator_name_) {
      return answer_;
    }
    if (static_cast<double>(request.utime) - static_cast<double>(now_utime) > kMaxAhead_us) {
      return refuse(fmt::format("request from {} at utime {} ignored: {:.1f} s ahead of this node's clock",
                                request.operator_name, request.utime,
                                (static_cast<double>(request.utime) - static_cast<double>(now_utime)) * 1e-6));
    }
    if (answered_ && request.utime < utime_) {
      return refuse(fmt::format("request from {} at utime {} ignored: older than the one acted on ({} at utime {})",
                                request.operator_name, request.utime, operator_name_, utime_));
    }
    fault_t answer = act();
    if (answer.code != static_cast<std::int32_t>(FaultCode::kOperatorAction)) return answer;
    answer_ = answer;
    answered_ = true;
    utime_ = request.utime;
    seq_ = request.seq;
    operator_name_ = request.operator_name;
    return answer_;
  }

 private:
  bool answered_ = false;
  std::int64_t utime_ = 0, seq_ = 0;
  std::string operator_name_;
  fault_t answer_{};
};

}  // namespace edsp
