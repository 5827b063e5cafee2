// The cueing delay's trace through a log's links, on links built by hand
// with known delays: each sample to the first setpoint that came from it,
// its command (or the next one, when the kinematics skipped it), that
// command's drive write (or the next one's); a sample a newer one overtook
// is not traced.
#include "edsp/cueing/cueing_delay.h"

#include <gtest/gtest.h>

namespace edsp {
namespace {

TEST(CueingDelay, EachSampleIsTracedToTheFirstDriveWriteOfACommandMadeFromIt) {
  // Samples 1..4 sent at 0, 4, 8, 12 ms; setpoints 100.. at 1 kHz carry the
  // newest sample's sequence; sample 3 was overtaken by 4 before any cue.
  const std::vector<SentSample> sent = {{1, 0}, {2, 4'000}, {3, 8'000}, {4, 8'500}};
  const std::vector<CueingSetpointLink> setpoints = {{100, 1, 1'000}, {101, 1, 2'000}, {102, 2, 4'200},
                                                     {103, 2, 5'000}, {104, 4, 9'000}, {105, 4, 10'000}};
  // Command 7 answers setpoint 102 late; setpoint 104's command was lost, 105's is 9.
  const std::vector<CommandLink> commands = {{5, 100}, {6, 101}, {7, 102}, {8, 103}, {9, 105}};
  // The bridge wrote command 5 at 1.2 ms, 7 at 5.1 ms (6 skipped), 9 at 10.3 ms.
  const std::vector<DriveWrite> writes = {{1'200, 5}, {2'200, 5}, {5'100, 7}, {6'100, 8}, {10'300, 9}};
  const CueingDelays d = TraceCueingDelays(sent, setpoints, commands, writes);
  EXPECT_EQ(d.sent, 4u);
  ASSERT_EQ(d.delays_s.size(), 3u) << "sample 3 never reached a cue";
  EXPECT_NEAR(d.delays_s[0], 1.2e-3, 1e-12);
  EXPECT_NEAR(d.delays_s[1], 1.1e-3, 1e-12);
  EXPECT_NEAR(d.delays_s[2], 1.8e-3, 1e-12) << "setpoint 104's command lost: 105's, written at 10.3 ms";
  EXPECT_NEAR(d.Percentile(0.5), 1.2e-3, 1e-12);
  EXPECT_NEAR(d.Percentile(1.0), 1.8e-3, 1e-12);
}

TEST(CueingDelay, ASenderRestartedInTheSameLogIsTracedToItsOwnSetpoints) {
  // Two sends, each numbering from 1: the second's sample 1 (sent at 50 ms)
  // to the setpoint logged after it, not the first send's.
  const std::vector<SentSample> sent = {{1, 0}, {1, 50'000}};
  const std::vector<CueingSetpointLink> setpoints = {{10, 1, 700}, {60, 1, 50'600}};
  const std::vector<CommandLink> commands = {{10, 10}, {60, 60}};
  const std::vector<DriveWrite> writes = {{1'300, 10}, {51'400, 60}};
  const CueingDelays d = TraceCueingDelays(sent, setpoints, commands, writes);
  ASSERT_EQ(d.delays_s.size(), 2u);
  EXPECT_NEAR(d.delays_s[0], 1.3e-3, 1e-12);
  EXPECT_NEAR(d.delays_s[1], 1.4e-3, 1e-12) << "not -48.7 ms through the first send's setpoint";
}

TEST(CueingDelay, NothingTracedGivesNoPercentile) {
  const CueingDelays d = TraceCueingDelays({{1, 0}}, {}, {}, {});
  EXPECT_EQ(d.sent, 1u);
  EXPECT_TRUE(d.delays_s.empty());
  EXPECT_EQ(d.Percentile(0.99), 0.0);
}

}  // namespace
}  // namespace edsp
