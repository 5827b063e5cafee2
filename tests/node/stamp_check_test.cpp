// A command's stamp against this host's clock: within the limit either way
// is on time, beyond it stale or from the future, and any int64 stamp (the
// sender's word) is judged without overflow (UBSan in the sanitized stage).
#include "edsp/node/stamp_check.h"

#include <gtest/gtest.h>

#include <limits>

namespace edsp {
namespace {

constexpr std::int64_t kNow = 1'764'000'000'000'000;  // 2025-11, µs

TEST(StampCheck, WithinTheLimitEitherWayIsOnTime) {
  EXPECT_EQ(StampProblem("x", kNow, kNow, 50000), std::nullopt);
  EXPECT_EQ(StampProblem("x", kNow - 50000, kNow, 50000), std::nullopt) << "the limit itself is still on time";
  EXPECT_EQ(StampProblem("x", kNow + 50000, kNow, 50000), std::nullopt);
}

TEST(StampCheck, BeyondItTheMessageSaysWhichWayAndByHowMuch) {
  EXPECT_EQ(StampProblem("leg command seq 7", kNow - 50001, kNow, 50000),
            "leg command seq 7 is 50001 us old (limit 50000 us)");
  EXPECT_EQ(StampProblem("setpoint seq 3", kNow + 120000, kNow, 50000),
            "setpoint seq 3 is stamped 120000 us in the future (limit 50000 us): the clocks of its host and this "
            "one disagree (docs/multihost.md)");
}

TEST(StampCheck, AnyInt64StampIsJudgedWithoutOverflow) {
  const std::string oldest = StampProblem("x", std::numeric_limits<std::int64_t>::min(), kNow, 50000).value_or("");
  EXPECT_NE(oldest.find("us old"), std::string::npos) << oldest;
  const std::string latest = StampProblem("x", std::numeric_limits<std::int64_t>::max(), kNow, 50000).value_or("");
  EXPECT_NE(latest.find("in the future"), std::string::npos) << latest;
  EXPECT_NE(StampProblem("x", 0, std::numeric_limits<std::int64_t>::max(), 50000), std::nullopt);
}

}  // namespace
}  // namespace edsp
