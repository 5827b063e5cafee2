// The relay of operators' requests, on a board filled as the bus would and
// a publisher that records: stamped by the server (session, operator,
// seq), the client's request_id kept, sent again every 0.5 s until its
// reply is on the board, given up after 5 s, and the refusals.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "encoded.h"  // tests/support

#include "edsp/channels.h"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/web/foxglove_protocol.h"
#include "edsp/web/request_relay.h"

namespace edsp::web {
namespace {

constexpr std::int64_t kMsNs = 1'000'000;

struct Sent {
  std::string channel;
  RequestMessage request;
};

template <typename Msg>
void Post(ChannelBoard* board, const char* channel, const Msg& msg) {
  const std::vector<std::uint8_t> bytes = test_support::Encoded(msg);
  board->Post(channel, 0, bytes.data(), bytes.size());
}

class Relay : public testing::Test {
 protected:
  RequestRelay MakeRelay(std::int64_t session) {
    return RequestRelay(
        &board_,
        [this](const std::string& channel, const RequestMessage& r) {
          sent_.push_back({channel, r});
          return true;
        },
        session);
  }
  ChannelBoard board_;
  std::vector<Sent> sent_;
};

TEST_F(Relay, ARequestIsStampedByTheServerAndKeepsTheClientsId) {
  RequestRelay relay = MakeRelay(42);
  const std::int64_t id = relay.Submit(
      channel::kMotionRequest, R"({"request_id": 77, "kind": 2, "session_id": 5, "client": "mallory", "seq": 9})",
      "web:alice", 0, 1'700'000'000'000'000);
  EXPECT_EQ(id, 77);
  ASSERT_EQ(sent_.size(), 1u);
  EXPECT_EQ(sent_[0].channel, channel::kMotionRequest);
  const auto& m = std::get<motion_request_t>(sent_[0].request);
  EXPECT_EQ(m.session_id, 42);       // the group's, not the client's 5
  EXPECT_EQ(m.client, "web:alice");  // the token's name, not "mallory"
  EXPECT_EQ(m.request_id, 77);
  EXPECT_EQ(m.utime, 1'700'000'000'000'000);
  EXPECT_EQ(m.seq, 1);

  relay.Submit(channel::kArm, R"({"request_id": 78, "operator_name": "mallory"})", "web:alice", 0, 1);
  EXPECT_EQ(std::get<arm_t>(sent_[1].request).operator_name, "web:alice");
  EXPECT_EQ(std::get<arm_t>(sent_[1].request).session_id, 42);
}

TEST_F(Relay, ItIsSentAgainUntilItsReplyComesThenNoMore) {
  RequestRelay relay = MakeRelay(42);
  relay.Submit(channel::kMotionRequest, R"({"request_id": 77, "kind": 1})", "web:alice", 0, 1);
  relay.Tick(400 * kMsNs);
  EXPECT_EQ(sent_.size(), 1u);  // not yet 0.5 s
  relay.Tick(500 * kMsNs);
  ASSERT_EQ(sent_.size(), 2u);
  EXPECT_EQ(std::get<motion_request_t>(sent_[1].request).seq, 2);
  EXPECT_EQ(std::get<motion_request_t>(sent_[1].request).utime, 1);  // the first stamp: as old as the request

  motion_reply_t other{};
  other.request_id = 76;  // someone else's reply
  Post(&board_, channel::kMotionReply, other);
  relay.Tick(1000 * kMsNs);
  EXPECT_EQ(sent_.size(), 3u);
  motion_reply_t reply{};
  reply.request_id = 77;
  Post(&board_, channel::kMotionReply, reply);
  relay.Tick(1500 * kMsNs);
  relay.Tick(3000 * kMsNs);
  EXPECT_EQ(sent_.size(), 3u);
  EXPECT_EQ(relay.pending(), 0u);
}

TEST_F(Relay, ANodesReplyAnswersTooAndAnUnansweredRequestIsGivenUpAfterFiveSeconds) {
  RequestRelay relay = MakeRelay(42);
  relay.Submit(channel::kArm, R"({"request_id": 5})", "web:alice", 0, 1);
  relay.Submit(channel::kPrMode, R"({"request_id": 6, "pr_mode": 2})", "web:alice", 0, 1);
  reply_t reply{};
  reply.request_id = 5;
  Post(&board_, channel::kReply, reply);
  relay.Tick(500 * kMsNs);
  EXPECT_EQ(relay.pending(), 1u);
  for (std::int64_t t = 1000; t <= 6000; t += 500) relay.Tick(t * kMsNs);
  EXPECT_EQ(relay.pending(), 0u);
  EXPECT_EQ(relay.sent(), 11);  // arm once; the PR mode at 0, 0.5, ..., 4.5 s
}

TEST_F(Relay, OnlyItsOwnReplyChannelAnswersARequest) {
  RequestRelay relay = MakeRelay(42);
  relay.Submit(channel::kMotionRequest, R"({"request_id": 77, "kind": 4})", "web:alice", 0, 1);
  reply_t not_the_planners{};
  not_the_planners.request_id = 77;  // a node's reply with the same id answers no motion request
  Post(&board_, channel::kReply, not_the_planners);
  relay.Tick(500 * kMsNs);
  EXPECT_EQ(relay.pending(), 1u);
  EXPECT_EQ(sent_.size(), 2u);
}

TEST_F(Relay, AClosedConnectionsRequestsAreSentNoMore) {
  RequestRelay relay = MakeRelay(42);
  relay.Submit(channel::kArm, R"({"request_id": 1})", "web:alice", 0, 1, /*owner=*/7);
  relay.Submit(channel::kArm, R"({"request_id": 2})", "web:bob", 0, 1, /*owner=*/8);
  relay.ForgetOwner(7);
  relay.Tick(500 * kMsNs);
  ASSERT_EQ(sent_.size(), 3u);
  EXPECT_EQ(std::get<arm_t>(sent_[2].request).request_id, 2);
}

TEST_F(Relay, WithoutAGivenSessionItIsThePlannersAndNoneKnownIsARefusal) {
  RequestRelay relay = MakeRelay(0);
  EXPECT_THROW(relay.Submit(channel::kArm, R"({"request_id": 5})", "web:alice", 0, 1), foxglove::ProtocolError);
  EXPECT_TRUE(sent_.empty());
  motion_status_t status{};
  status.session_id = 31;
  Post(&board_, channel::kMotionStatus, status);
  relay.Submit(channel::kArm, R"({"request_id": 5})", "web:alice", 0, 1);
  EXPECT_EQ(std::get<arm_t>(sent_.at(0).request).session_id, 31);
}

TEST_F(Relay, NoIdAPendingIdAndFieldsThatAreWrongAreRefusedAndNothingIsSent) {
  RequestRelay relay = MakeRelay(42);
  EXPECT_THROW(relay.Submit(channel::kArm, R"({})", "web:alice", 0, 1), foxglove::ProtocolError);
  EXPECT_THROW(relay.Submit(channel::kSetpoint, R"({"request_id": 1})", "web:alice", 0, 1), foxglove::ProtocolError);
  EXPECT_THROW(relay.Submit(channel::kMotionRequest, R"({"request_id": 1, "pose": 3})", "web:alice", 0, 1),
               foxglove::ProtocolError);
  EXPECT_TRUE(sent_.empty());
  relay.Submit(channel::kArm, R"({"request_id": 9})", "web:alice", 0, 1);
  EXPECT_THROW(relay.Submit(channel::kArm, R"({"request_id": 9})", "web:bob", 0, 1), foxglove::ProtocolError);
  EXPECT_EQ(sent_.size(), 1u);
}

}  // namespace
}  // namespace edsp::web
