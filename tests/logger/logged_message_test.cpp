// A setpoint read from a log as today's type, whichever layout recorded it:
// the older one's phase from the labels its planners wrote, its fields
// carried over; bytes of another type or cut short are no setpoint.
#include "edsp/logger/logged_message.h"

#include <gtest/gtest.h>

#include "edsp/pose_setpoint_v1_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "encoded.h"  // tests/support

namespace edsp {
namespace {

LogEvent EventOf(const std::vector<std::uint8_t>& bytes) {
  LogEvent event;
  event.channel = "EDSP_SETPOINT";
  event.data = bytes;
  return event;
}

pose_setpoint_t ReadOlder(const std::string& label) {
  pose_setpoint_v1_t old{};
  old.utime = 1'500'000;
  old.seq = 7;
  old.session_id = 3;
  old.pose[2] = 1.6;
  old.velocity[5] = 0.2;
  old.acceleration[0] = -0.5;
  old.trajectory = label;
  old.segment = 4;
  pose_setpoint_t read{};
  EXPECT_TRUE(DecodeEvent(EventOf(test_support::Encoded(old)), &read)) << label;
  EXPECT_EQ(read.trajectory, label);
  EXPECT_EQ(read.utime, old.utime);
  EXPECT_EQ(read.seq, old.seq);
  EXPECT_EQ(read.session_id, old.session_id);
  EXPECT_EQ(read.pose[2], old.pose[2]);
  EXPECT_EQ(read.velocity[5], old.velocity[5]);
  EXPECT_EQ(read.acceleration[0], old.acceleration[0]);
  EXPECT_EQ(read.segment, old.segment);
  return read;
}

// The older layout's fingerprint is what lcm-gen gave pose_setpoint_t
// before it had a phase (an independent truth: generated from the .lcm
// file as it was).
TEST(LoggedMessage, ASetpointOfTheOlderLayoutReadsWithThePhaseItsLabelMeant) {
  EXPECT_EQ(static_cast<std::uint64_t>(pose_setpoint_v1_t::getHash()), 0xa6660ef6924ff02aULL);
  EXPECT_NE(pose_setpoint_v1_t::getHash(), pose_setpoint_t::getHash());
  EXPECT_EQ(ReadOlder("Lz/dwell 3").phase, pose_setpoint_t::PHASE_DWELL);
  EXPECT_EQ(ReadOlder("cal2/dwell 5").phase, pose_setpoint_t::PHASE_DWELL);
  EXPECT_EQ(ReadOlder("Lz/move 3").phase, pose_setpoint_t::PHASE_MOVE);
  EXPECT_EQ(ReadOlder("jog z -0.004").phase, pose_setpoint_t::PHASE_MOVE);
  EXPECT_EQ(ReadOlder("cueing").phase, pose_setpoint_t::PHASE_CUEING);
  EXPECT_EQ(ReadOlder("hold").phase, pose_setpoint_t::PHASE_HOLD);
}

TEST(LoggedMessage, TodaysSetpointKeepsItsOwnPhaseAndOtherBytesAreNoSetpoint) {
  pose_setpoint_t sent{};
  sent.trajectory = "Lz/dwell 3";  // the label says dwell, the phase says otherwise: the phase wins
  sent.phase = pose_setpoint_t::PHASE_MOVE;
  pose_setpoint_t read{};
  ASSERT_TRUE(DecodeEvent(EventOf(test_support::Encoded(sent)), &read));
  EXPECT_EQ(read.phase, pose_setpoint_t::PHASE_MOVE);

  tracker_point_t point{};
  EXPECT_FALSE(DecodeEvent(EventOf(test_support::Encoded(point)), &read));
  std::vector<std::uint8_t> cut = test_support::Encoded(sent);
  cut.resize(cut.size() - 3);
  EXPECT_FALSE(DecodeEvent(EventOf(cut), &read));
  pose_setpoint_v1_t old{};
  old.trajectory = "Lz/dwell 1";
  std::vector<std::uint8_t> old_cut = test_support::Encoded(old);
  old_cut.resize(old_cut.size() - 3);
  EXPECT_FALSE(DecodeEvent(EventOf(old_cut), &read));
}

}  // namespace
}  // namespace edsp
