// Operator requests arrive more than once (edsp-ctl resends until it hears
// an answer): each is acted on once, its copies get the same answer, and a
// request older than the one acted on is refused, never acted on. A
// refusal is not remembered, and a request from the future is refused.
#include <gtest/gtest.h>

#include "edsp/arm_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/operator_requests.h"

namespace edsp {
namespace {

arm_t Request(std::int64_t utime, std::int64_t seq, const std::string& who) {
  arm_t r{};
  r.utime = utime;
  r.seq = seq;
  r.operator_name = who;
  return r;
}

constexpr std::int64_t kRequestNow = 5000;

struct Counter {
  int acted = 0;
  fault_t Act() {
    fault_t f{};
    f.code = static_cast<std::int32_t>(FaultCode::kOperatorAction);
    f.reason = "acted " + std::to_string(++acted);
    return f;
  }
};

fault_t Refuse(const std::string& reason) {
  fault_t f{};
  f.reason = "refused: " + reason;
  return f;
}

TEST(OperatorRequestAnswers, ActsOnceAndAnswersEveryCopyAlike) {
  OperatorRequestAnswers answers;
  Counter c;
  const arm_t a = Request(1000, 1, "alice");
  EXPECT_EQ(answers
                .Answer(
                    a, kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 1");
  EXPECT_EQ(answers
                .Answer(
                    a, kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 1");
  EXPECT_EQ(answers
                .Answer(
                    a, kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 1");
  EXPECT_EQ(c.acted, 1);
}

TEST(OperatorRequestAnswers, ANewRequestIsActedOnEvenWithTheSameTimeOrSeq) {
  OperatorRequestAnswers answers;
  Counter c;
  answers.Answer(
      Request(1000, 1, "alice"), kRequestNow, [&] { return c.Act(); }, Refuse);
  EXPECT_EQ(answers
                .Answer(
                    Request(1000, 2, "alice"), kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 2");
  EXPECT_EQ(answers
                .Answer(
                    Request(1000, 2, "bob"), kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 3");
  EXPECT_EQ(answers
                .Answer(
                    Request(2000, 2, "bob"), kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 4");
}

TEST(OperatorRequestAnswers, ALateCopyOfAnOlderRequestIsRefusedNotActedOn) {
  OperatorRequestAnswers answers;
  Counter c;
  const arm_t first = Request(1000, 1, "alice"), second = Request(2000, 1, "bob");
  answers.Answer(
      first, kRequestNow, [&] { return c.Act(); }, Refuse);
  answers.Answer(
      second, kRequestNow, [&] { return c.Act(); }, Refuse);
  const fault_t late = answers.Answer(
      first, kRequestNow, [&] { return c.Act(); }, Refuse);
  EXPECT_EQ(c.acted, 2);
  EXPECT_EQ(late.reason,
            "refused: request from alice at utime 1000 ignored: older than the one acted on (bob at utime 2000)");
  // The one in force is still answered alike.
  EXPECT_EQ(answers
                .Answer(
                    second, kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 2");
}

// A request the node refused (another session's, a value it cannot take)
// is not remembered: a copy is judged again, and it holds no later request
// back, however it was stamped.
TEST(OperatorRequestAnswers, ARefusalHoldsNothingBack) {
  OperatorRequestAnswers answers;
  Counter c;
  auto refuse = [] {
    fault_t f{};
    f.code = static_cast<std::int32_t>(FaultCode::kForeignSession);
    f.reason = "not yours";
    return f;
  };
  EXPECT_EQ(answers.Answer(Request(4000, 1, "mallory"), kRequestNow, refuse, Refuse).reason, "not yours");
  EXPECT_EQ(answers
                .Answer(
                    Request(1000, 1, "alice"), kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 1");
  EXPECT_EQ(c.acted, 1);
}

// A stamp from the future (a sender's clock far ahead, or a forged one at
// the int64 limit) would hold back every request after it: refused, and
// judged without overflow.
TEST(OperatorRequestAnswers, ARequestFromTheFutureIsRefused) {
  OperatorRequestAnswers answers;
  Counter c;
  const fault_t ahead = answers.Answer(
      Request(kRequestNow + 20000000, 1, "alice"), kRequestNow, [&] { return c.Act(); }, Refuse);
  EXPECT_EQ(ahead.reason, "refused: request from alice at utime 20005000 ignored: 20.0 s ahead of this node's clock");
  const fault_t forged = answers.Answer(
      Request(INT64_MAX, 1, "mallory"), INT64_MIN, [&] { return c.Act(); }, Refuse);
  EXPECT_NE(forged.reason.find("ahead of this node's clock"), std::string::npos) << forged.reason;
  EXPECT_EQ(c.acted, 0);
  // Within the clocks' tolerance it is acted on.
  EXPECT_EQ(answers
                .Answer(
                    Request(kRequestNow + 5000000, 1, "bob"), kRequestNow, [&] { return c.Act(); }, Refuse)
                .reason,
            "acted 1");
}

}  // namespace
}  // namespace edsp
