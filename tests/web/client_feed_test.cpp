// A client's feed on a board filled as the bus would, on a clock of the
// test's own: the rate cap of a cyclic channel (and the newest message, not
// a backlog), every message of an event channel in order, what a slow
// client lost counted, and the protocol's refusals.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "encoded.h"  // tests/support

#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/web/client_feed.h"
#include "edsp/web/foxglove_protocol.h"

namespace edsp::web {
namespace {

using json = nlohmann::ordered_json;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::size_t kAll = 100'000;  // no frame budget

template <typename Msg>
void Post(ChannelBoard* board, const char* channel, const Msg& msg, std::int64_t at_ns) {
  const std::vector<std::uint8_t> bytes = test_support::Encoded(msg);
  board->Post(channel, at_ns, bytes.data(), bytes.size());
}

std::uint32_t IdOf(const char* channel) { return static_cast<std::uint32_t>(ChannelBoard::IndexOf(channel) + 1); }

leg_state_t LegState(std::int64_t seq) {
  leg_state_t s{};
  s.seq = seq;
  return s;
}

fault_t Fault(std::int64_t seq) {
  fault_t f{};
  f.seq = seq;
  f.reason = "fault " + std::to_string(seq);
  return f;
}

TEST(ChannelBoard, EventChannelsAreTheTablesOnEventRows) {
  for (const channel::Channel& c : channel::kChannels) {
    EXPECT_EQ(ChannelBoard::KeepsEveryMessage(ChannelBoard::IndexOf(c.name)), c.rate_hz == 0.0) << c.name;
  }
  EXPECT_EQ(ChannelBoard::IndexOf("NOT_EDSP"), ChannelBoard::ChannelCount());
}

// 1 kHz in, a tick every 5 ms for 10 s: 30 frames a second, each the newest
// message there was at its tick.
TEST(ClientFeed, ACyclicChannelComesAtTheCapAndAlwaysTheNewest) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(7, IdOf(channel::kLegState));
  std::int64_t frames = 0;
  std::int64_t newest_seq = 0;
  for (std::int64_t ms = 0; ms < 10'000; ++ms) {
    Post(&board, channel::kLegState, LegState(ms + 1), ms * kMs);
    newest_seq = ms + 1;
    if (ms % 5 != 0) continue;
    for (const FeedFrame& f : feed.Due(ms * kMs, kAll)) {
      EXPECT_EQ(f.subscription_id, 7u);
      EXPECT_EQ(json::parse(*f.json).at("seq").get<std::int64_t>(), newest_seq);
      EXPECT_EQ(f.receive_ns, ms * kMs);
      ++frames;
    }
  }
  EXPECT_GE(frames, 299);  // 30 Hz over 10 s, on a 5 ms grid
  EXPECT_LE(frames, 301);
}

TEST(ClientFeed, NothingNewIsNotSentAgainAndAStallGivesOneFrameNotABurst) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(1, IdOf(channel::kLegState));
  EXPECT_TRUE(feed.Due(0, kAll).empty());  // nothing posted yet
  Post(&board, channel::kLegState, LegState(1), 0);
  EXPECT_EQ(feed.Due(1 * kMs, kAll).size(), 1u);
  EXPECT_TRUE(feed.Due(100 * kMs, kAll).empty());  // the same message: not again
  // The client's socket took nothing for 2 s; then the newest, once.
  for (int i = 2; i < 2000; ++i) Post(&board, channel::kLegState, LegState(i), i * kMs);
  EXPECT_EQ(feed.Due(2000 * kMs, kAll).size(), 1u);
  Post(&board, channel::kLegState, LegState(2001), 2001 * kMs);
  EXPECT_TRUE(feed.Due(2005 * kMs, kAll).empty());  // a cap's interval (33 ms) has not passed
  EXPECT_EQ(feed.Due(2034 * kMs, kAll).size(), 1u);
}

TEST(ClientFeed, AnEventChannelGivesEveryMessageInOrderBeyondTheCap) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  Post(&board, channel::kFault, Fault(0), 0);  // before the subscription: not sent
  feed.Subscribe(2, IdOf(channel::kFault));
  for (int i = 1; i <= 50; ++i) Post(&board, channel::kFault, Fault(i), i);  // 50 within a microsecond
  const auto frames = feed.Due(1 * kMs, kAll);
  ASSERT_EQ(frames.size(), 50u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(json::parse(*frames[i].json).at("seq").get<int>(), i + 1);
  EXPECT_TRUE(feed.Due(2 * kMs, kAll).empty());
  EXPECT_EQ(feed.lost(), 0u);
}

TEST(ClientFeed, WhatTheBoardOverwroteBeforeASlowClientReadIsCounted) {
  ChannelBoard board(16);
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(2, IdOf(channel::kFault));
  for (int i = 1; i <= 40; ++i) Post(&board, channel::kFault, Fault(i), i);
  const auto frames = feed.Due(1 * kMs, kAll);
  ASSERT_EQ(frames.size(), 16u);
  EXPECT_EQ(json::parse(*frames.front().json).at("seq").get<int>(), 25);
  EXPECT_EQ(feed.lost(), 24u);
}

TEST(ClientFeed, ABurstOfEventsComesWithinTheFrameBudgetInOrderAndNoneIsLost) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(2, IdOf(channel::kFault));
  for (int i = 1; i <= 300; ++i) Post(&board, channel::kFault, Fault(i), i);
  std::vector<int> seqs;
  for (int call = 0; call < 3; ++call) {
    const auto frames = feed.Due(call * kMs, 128);
    EXPECT_LE(frames.size(), 128u);
    for (const FeedFrame& f : frames) seqs.push_back(json::parse(*f.json).at("seq").get<int>());
  }
  ASSERT_EQ(seqs.size(), 300u);
  for (int i = 0; i < 300; ++i) EXPECT_EQ(seqs[i], i + 1);
  EXPECT_EQ(feed.lost(), 0u);
}

TEST(ClientFeed, TextThatIsNotUtf8IsSentMendedNotDropped) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(2, IdOf(channel::kFault));
  fault_t f = Fault(1);
  f.reason = "drive \xff\xfe says";
  Post(&board, channel::kFault, f, 0);
  const auto frames = feed.Due(1 * kMs, kAll);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(json::parse(*frames[0].json).at("reason"), "drive \xEF\xBF\xBD\xEF\xBF\xBD says");
  EXPECT_EQ(board.undecodable(), 0u);
}

TEST(ClientFeed, UndecodableBytesAreCountedAndNeverSent) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(1, IdOf(channel::kLegState));
  feed.Subscribe(2, IdOf(channel::kFault));
  const std::uint8_t junk[5] = {1, 2, 3, 4, 5};
  board.Post(channel::kLegState, 0, junk, sizeof junk);
  board.Post(channel::kFault, 0, junk, sizeof junk);
  EXPECT_TRUE(feed.Due(1 * kMs, kAll).empty());
  EXPECT_TRUE(feed.Due(100 * kMs, kAll).empty());  // and not later either, from what was kept of it
  ClientFeed second(&board, 30.0);
  second.Subscribe(1, IdOf(channel::kLegState));
  EXPECT_TRUE(second.Due(200 * kMs, kAll).empty());
  EXPECT_EQ(board.undecodable(), 2u);
  board.Post("NOT_EDSP", 0, junk, sizeof junk);  // not a channel of the table: ignored
  EXPECT_EQ(board.undecodable(), 2u);
}

TEST(ClientFeed, SubscriptionsTheProtocolForbidsAreRefusedByName) {
  ChannelBoard board;
  ClientFeed feed(&board, 30.0);
  feed.Subscribe(1, 1);
  EXPECT_THROW(feed.Subscribe(1, 2), foxglove::ProtocolError);  // id in use
  EXPECT_THROW(feed.Subscribe(2, 0), foxglove::ProtocolError);
  EXPECT_THROW(feed.Subscribe(2, static_cast<std::uint32_t>(ChannelBoard::ChannelCount() + 1)),
               foxglove::ProtocolError);
  EXPECT_THROW(feed.Unsubscribe(9), foxglove::ProtocolError);
  EXPECT_THROW(feed.Subscribe(3, 1), foxglove::ProtocolError);  // the same channel twice
  feed.Unsubscribe(1);
  EXPECT_EQ(feed.subscriptions(), 0u);
  feed.Subscribe(1, 2);  // an id may be used again after its unsubscribe
  EXPECT_EQ(feed.subscriptions(), 1u);
}

}  // namespace
}  // namespace edsp::web
