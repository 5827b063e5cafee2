// WatchedSilence against the wall clock it replaces: equal while the reader
// keeps its time, blind to the reader's own pauses, and never more than the
// wall clock.

#include "edsp/transport/watched_silence.h"

#include <gtest/gtest.h>

namespace edsp {
namespace {

constexpr std::int64_t kStartUs = 1'000'000;

TEST(WatchedSilence, WhileTheReaderKeepsItsTimeItIsTheWallClocksSilence) {
  WatchedSilence silence;
  silence.Heard(kStartUs);
  std::int64_t now = kStartUs;
  for (int look = 0; look < 60; ++look) {
    now += timing::kCycleUs;
    EXPECT_EQ(silence.Missed(now), now - kStartUs);
  }
}

TEST(WatchedSilence, TheReadersOwnPauseCountsOneLapseAtMost) {
  // The whole host stood 49 ms, reader and source alike: the first look
  // after it has watched one lapse of that, not 49 ms.
  WatchedSilence silence;
  silence.Heard(kStartUs);
  EXPECT_EQ(silence.Missed(kStartUs + timing::kCycleUs), timing::kCycleUs);
  EXPECT_EQ(silence.Missed(kStartUs + timing::kCycleUs + 49'000), timing::kCycleUs + timing::kFeedForwardLapseUs);
  // A reader that keeps its time from there counts again at the wall's rate.
  EXPECT_EQ(silence.Missed(kStartUs + timing::kCycleUs + 50'000), 2 * timing::kCycleUs + timing::kFeedForwardLapseUs);
}

TEST(WatchedSilence, ASourceSilentThroughAStarvedReaderIsStillFoundSilent) {
  // A reader looking only every 10 ms counts 2.5 ms a look: a 50 ms limit
  // is reached after 20 looks, 200 ms of wall clock, never before the wall.
  WatchedSilence silence;
  silence.Heard(kStartUs);
  std::int64_t now = kStartUs;
  int looks = 0;
  while (silence.silent_us() <= 50'000) {
    now += 10'000;
    silence.Missed(now);
    ++looks;
    ASSERT_LE(silence.silent_us(), now - kStartUs);
  }
  EXPECT_EQ(looks, 21);
}

TEST(WatchedSilence, ANewMessageStartsTheSilenceAgainAndTheFirstLookCountsNothing) {
  WatchedSilence silence;
  EXPECT_EQ(silence.Missed(kStartUs), 0);  // no look before it to measure from
  EXPECT_EQ(silence.Missed(kStartUs + 2000), 2000);
  silence.Heard(kStartUs + 3000);
  EXPECT_EQ(silence.silent_us(), 0);
  EXPECT_EQ(silence.Missed(kStartUs + 4000), 1000);
  // A clock read out of order (two threads' stamps) adds nothing.
  EXPECT_EQ(silence.Missed(kStartUs + 3500), 1000);
}

}  // namespace
}  // namespace edsp
