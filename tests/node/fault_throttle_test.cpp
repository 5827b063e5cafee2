// A flood of identical faults becomes one report per interval that says how
// many it stands for; different channels or codes are throttled separately.
#include <gtest/gtest.h>

#include "edsp/node/fault.h"

namespace edsp {
namespace {

fault_t Fault(const char* channel, FaultCode code, std::int64_t utime) {
  return MakeFault("kinematics", channel, code, fault_t::SEVERITY_ERROR, "refused", utime);
}

TEST(FaultThrottle, OnePerIntervalPerChannelAndCodeWithTheSuppressedCount) {
  FaultThrottle throttle(100000);
  int sent = 0;
  for (std::int64_t t = 0; t < 1000000; t += 1000) {  // 1 kHz for 1 s
    fault_t f = Fault("EDSP_SETPOINT", FaultCode::kForeignSession, t);
    if (throttle.Admit(&f)) {
      ++sent;
      if (t > 0) {
        EXPECT_NE(f.reason.find("and 99 more like it"), std::string::npos) << f.reason;
      }
    }
  }
  EXPECT_EQ(sent, 10);
  EXPECT_EQ(throttle.suppressed_total(), 990);
  fault_t other_code = Fault("EDSP_SETPOINT", FaultCode::kStale, 1000000);
  fault_t other_channel = Fault("EDSP_LEG_STATE", FaultCode::kForeignSession, 1000000);
  EXPECT_TRUE(throttle.Admit(&other_code));
  EXPECT_TRUE(throttle.Admit(&other_channel));
}

}  // namespace
}  // namespace edsp
