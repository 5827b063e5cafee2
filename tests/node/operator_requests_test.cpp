// Operator requests arrive more than once (edsp-ctl resends until it hears
// an answer): each is acted on once, its copies get the same answer, and a
// request older than the one acted on is refused, never acted on.
#include <gtest/gtest.h>

#include "edsp/arm_t.hpp"
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

struct Counter {
  int acted = 0;
  fault_t Act() {
    fault_t f{};
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
  EXPECT_EQ(answers.Answer(a, [&] { return c.Act(); }, Refuse).reason, "acted 1");
  EXPECT_EQ(answers.Answer(a, [&] { return c.Act(); }, Refuse).reason, "acted 1");
  EXPECT_EQ(answers.Answer(a, [&] { return c.Act(); }, Refuse).reason, "acted 1");
  EXPECT_EQ(c.acted, 1);
}

TEST(OperatorRequestAnswers, ANewRequestIsActedOnEvenWithTheSameTimeOrSeq) {
  OperatorRequestAnswers answers;
  Counter c;
  answers.Answer(Request(1000, 1, "alice"), [&] { return c.Act(); }, Refuse);
  EXPECT_EQ(answers.Answer(Request(1000, 2, "alice"), [&] { return c.Act(); }, Refuse).reason, "acted 2");
  EXPECT_EQ(answers.Answer(Request(1000, 2, "bob"), [&] { return c.Act(); }, Refuse).reason, "acted 3");
  EXPECT_EQ(answers.Answer(Request(2000, 2, "bob"), [&] { return c.Act(); }, Refuse).reason, "acted 4");
}

TEST(OperatorRequestAnswers, ALateCopyOfAnOlderRequestIsRefusedNotActedOn) {
  OperatorRequestAnswers answers;
  Counter c;
  const arm_t first = Request(1000, 1, "alice"), second = Request(2000, 1, "bob");
  answers.Answer(first, [&] { return c.Act(); }, Refuse);
  answers.Answer(second, [&] { return c.Act(); }, Refuse);
  const fault_t late = answers.Answer(first, [&] { return c.Act(); }, Refuse);
  EXPECT_EQ(c.acted, 2);
  EXPECT_EQ(late.reason,
            "refused: request from alice at utime 1000 ignored: older than the one acted on (bob at utime 2000)");
  // The one in force is still answered alike.
  EXPECT_EQ(answers.Answer(second, [&] { return c.Act(); }, Refuse).reason, "acted 2");
}

}  // namespace
}  // namespace edsp
