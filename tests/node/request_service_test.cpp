// Requests arrive more than once (a client resends until it hears the
// reply): each request_id is acted on once and its copies get the same
// reply; another group's, an id of 0 and a stamp outside the window are
// refused with their codes and never acted on; for a switch, a request
// stamped before the last one acted on is refused. Stamps are any int64.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "edsp/arm_t.hpp"
#include "edsp/node/request_service.h"
#include "edsp/reply_t.hpp"

namespace edsp {
namespace {

constexpr std::int64_t kServiceSession = 42;
constexpr std::int64_t kServiceNow = 1'000'000'000;

arm_t ArmRequest(std::int64_t id, std::int64_t utime = kServiceNow, std::int64_t session = kServiceSession) {
  arm_t r{};
  r.utime = utime;
  r.session_id = session;
  r.request_id = id;
  r.operator_name = "alice";
  return r;
}

reply_t MakeReply(ReplyCode code, std::string reason) {
  reply_t r{};
  r.code = static_cast<std::int8_t>(code);
  r.reason = std::move(reason);
  return r;
}

struct ServiceNode {
  explicit ServiceNode(bool is_switch = false) : service(RequestPolicy{kServiceSession, 5.0, is_switch}) {}
  RequestService<reply_t> service;
  int acted = 0;
  ReplyCode next = ReplyCode::kDone;
  RequestService<reply_t>::Answer Ask(const arm_t& r, std::int64_t now = kServiceNow) {
    return service.Handle(r, now, MakeReply, [&] { return MakeReply(next, "acted " + std::to_string(++acted)); });
  }
};

TEST(RequestService, ActsOnceAndAnswersEveryCopyAlike) {
  ServiceNode node;
  const auto first = node.Ask(ArmRequest(7));
  EXPECT_TRUE(first.acted);
  EXPECT_EQ(first.reply.reason, "acted 1");
  EXPECT_EQ(first.reply.request_id, 7);
  EXPECT_EQ(first.reply.session_id, kServiceSession);
  EXPECT_EQ(first.reply.utime, kServiceNow);
  for (int copy = 0; copy < 3; ++copy) {
    const auto again =
        node.Ask(ArmRequest(7, kServiceNow + 500'000), kServiceNow + 600'000);  // re-stamped by the client
    EXPECT_FALSE(again.acted);
    EXPECT_EQ(again.reply.reason, "acted 1");
    EXPECT_EQ(again.reply.seq, first.reply.seq);
  }
  EXPECT_EQ(node.acted, 1);
  EXPECT_EQ(node.Ask(ArmRequest(8)).reply.reason, "acted 2");
}

TEST(RequestService, ARefusalOnItsMeritsIsAnsweredAlikeAndHoldsNothingBack) {
  ServiceNode node(true);
  node.next = ReplyCode::kInvalid;
  EXPECT_EQ(node.Ask(ArmRequest(1, kServiceNow + 1000)).reply.code, reply_t::CODE_INVALID);
  EXPECT_EQ(node.Ask(ArmRequest(1, kServiceNow + 1000)).reply.reason, "acted 1");  // the copy: the same refusal
  node.next = ReplyCode::kDone;
  // Stamped before the refused one: a refusal holds no later switch back.
  const auto done = node.Ask(ArmRequest(2, kServiceNow));
  EXPECT_EQ(done.reply.code, reply_t::CODE_DONE);
  EXPECT_EQ(node.acted, 2);
}

TEST(RequestService, AnotherGroupsRequestOrOneWithoutAnIdIsRefusedAndNeverActedOn) {
  ServiceNode node;
  const auto other = node.Ask(ArmRequest(7, kServiceNow, kServiceSession + 1));
  EXPECT_EQ(other.reply.code, reply_t::CODE_OTHER_SESSION);
  EXPECT_FALSE(other.acted);
  EXPECT_NE(other.reply.reason.find("session 43"), std::string::npos) << other.reply.reason;
  EXPECT_EQ(node.Ask(ArmRequest(0)).reply.code, reply_t::CODE_INVALID);
  EXPECT_EQ(node.acted, 0);
  // The same id from this group is still new.
  EXPECT_TRUE(node.Ask(ArmRequest(7)).acted);
}

// A log replayed later, or a sender whose clock is off, either way and at
// the int64 limits: stale, without overflow.
TEST(RequestService, AStampOutsideTheWindowIsStale) {
  ServiceNode node;
  constexpr std::int64_t kLowest = std::numeric_limits<std::int64_t>::min();
  constexpr std::int64_t kHighest = std::numeric_limits<std::int64_t>::max();
  EXPECT_EQ(node.Ask(ArmRequest(1, kServiceNow - 6'000'000)).reply.code, reply_t::CODE_STALE);
  EXPECT_EQ(node.Ask(ArmRequest(2, kServiceNow + 6'000'000)).reply.code, reply_t::CODE_STALE);
  EXPECT_EQ(node.Ask(ArmRequest(3, kHighest), kLowest).reply.code, reply_t::CODE_STALE);
  EXPECT_EQ(node.Ask(ArmRequest(4, kLowest), kHighest).reply.code, reply_t::CODE_STALE);
  EXPECT_EQ(node.acted, 0);
  EXPECT_EQ(node.Ask(ArmRequest(5, kServiceNow + 4'900'000)).reply.code, reply_t::CODE_DONE);
}

// A switch (a mode, a calibration): a request stamped before the last one
// acted on must not undo it, but a late copy of the one acted on still
// gets its reply.
TEST(RequestService, ASwitchRefusesARequestOlderThanTheOneActedOn) {
  ServiceNode node(true);
  const auto newer = node.Ask(ArmRequest(2, kServiceNow));
  ASSERT_EQ(newer.reply.code, reply_t::CODE_DONE);
  const auto older = node.Ask(ArmRequest(1, kServiceNow - 1'000'000));
  EXPECT_EQ(older.reply.code, reply_t::CODE_STALE);
  EXPECT_NE(older.reply.reason.find("before the last one acted on"), std::string::npos) << older.reply.reason;
  EXPECT_EQ(node.Ask(ArmRequest(2, kServiceNow - 2'000'000)).reply.reason, "acted 1");  // a late copy of it
  EXPECT_EQ(node.acted, 1);
  // Not a switch (motions queue): the older one is acted on.
  ServiceNode motions;
  motions.Ask(ArmRequest(2, kServiceNow));
  EXPECT_EQ(motions.Ask(ArmRequest(1, kServiceNow - 1'000'000)).reply.code, reply_t::CODE_DONE);
}

// The replies kept stay bounded by time, and a copy that comes after its
// reply was forgotten is older than the window (a client stamps a request
// once): stale, never acted on a second time.
TEST(RequestService, ACopyAfterItsReplyWasForgottenIsStaleNotActedOnAgain) {
  ServiceNode node;
  node.Ask(ArmRequest(1));
  const std::int64_t later = kServiceNow + 11'000'000;
  node.Ask(ArmRequest(2, later), later);  // evicts what is older than 10 s
  const auto again = node.Ask(ArmRequest(1), later);
  EXPECT_FALSE(again.acted);
  EXPECT_EQ(again.reply.code, reply_t::CODE_STALE);
  EXPECT_EQ(node.acted, 2);
  // Replayed stamps at the int64 limits evict without overflow.
  constexpr std::int64_t kLowest = std::numeric_limits<std::int64_t>::min();
  EXPECT_EQ(node.Ask(ArmRequest(3, kLowest), kLowest).reply.code, reply_t::CODE_DONE);
}

}  // namespace
}  // namespace edsp
