#pragma once
// An operator's request (EDSP_ARM, EDSP_PR_MODE) travels as one UDP
// datagram and so does the node's answer; either can be lost. edsp-ctl
// therefore sends the same request again until it hears an answer. The node
// acts on a request once and answers each copy with the answer it gave (a
// re-arm is not repeated, the confirmation names the switch that was made),
// and never acts on a request older than the last one it acted on (a late
// copy must not undo a later operator's command).

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "edsp/fault_t.hpp"

namespace edsp {

class OperatorRequestAnswers {
 public:
  // `act()` → fault_t for a new request; the same answer for a copy of the
  // last one (same utime, seq and operator); `refuse(reason)` → fault_t for
  // one older than the last.
  template <typename Request, typename Act, typename Refuse>
  fault_t Answer(const Request& request, Act act, Refuse refuse) {
    if (answered_ && request.utime == utime_ && request.seq == seq_ && request.operator_name == operator_name_) {
      return answer_;
    }
    if (answered_ && request.utime < utime_) {
      return refuse(fmt::format("request from {} at utime {} ignored: older than the one acted on ({} at utime {})",
                                request.operator_name, request.utime, operator_name_, utime_));
    }
    answer_ = act();
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
