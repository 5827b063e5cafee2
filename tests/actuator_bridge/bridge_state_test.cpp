// The bridge's state machine: the table against its specification, one
// expectation per (state, event) pair, then a tour of every transition
// through a running bridge, so the bridge is seen to take each one.
#include "edsp/actuator_bridge/bridge_state.h"

#include <array>
#include <set>
#include <utility>
#include <string>

#include <gtest/gtest.h>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/kinematics/config.h"
#include "recording_backend.h"

namespace edsp {
// Named, not anonymous: its helpers share names with other tests of its binary.
namespace bridge_state_table {

using S = BridgeState;
using E = BridgeEvent;

constexpr std::array<S, 5> kStates{S::kStartupHold, S::kFollowing, S::kLatched, S::kArmed, S::kRejoining};
constexpr std::array<E, 6> kEvents{E::kCommandAccepted, E::kCaughtUp, E::kStale,
                                   E::kDrivesLost,      E::kRearm,    E::kStreamAhead};

struct Expected {
  S from;
  E event;
  bool allowed;
  S to;
};

// The specification, written out pair by pair (docs/stack.md draws it);
// the test checks that its pairs are distinct and cover the table.
constexpr Expected kSpec[] = {
    {S::kStartupHold, E::kCommandAccepted, true, S::kFollowing},
    {S::kStartupHold, E::kCaughtUp, false, S::kStartupHold},
    {S::kStartupHold, E::kStale, true, S::kStartupHold},       // nothing to hold but where it is
    {S::kStartupHold, E::kDrivesLost, true, S::kStartupHold},  // an outage at start-up delays the start
    {S::kStartupHold, E::kRearm, true, S::kArmed},             // a restarted bridge joins a stream elsewhere
    {S::kFollowing, E::kCommandAccepted, true, S::kFollowing},
    {S::kFollowing, E::kCaughtUp, false, S::kStartupHold},
    {S::kFollowing, E::kStale, true, S::kLatched},
    {S::kFollowing, E::kDrivesLost, true, S::kLatched},
    {S::kFollowing, E::kRearm, true, S::kFollowing},
    {S::kLatched, E::kCommandAccepted, false, S::kStartupHold},  // only a re-arm leaves
    {S::kLatched, E::kCaughtUp, false, S::kStartupHold},
    {S::kLatched, E::kStale, true, S::kLatched},
    {S::kLatched, E::kDrivesLost, true, S::kLatched},
    {S::kLatched, E::kRearm, true, S::kArmed},
    {S::kArmed, E::kCommandAccepted, true, S::kRejoining},
    {S::kArmed, E::kCaughtUp, false, S::kStartupHold},
    {S::kArmed, E::kStale, true, S::kArmed},  // waits for its stream
    {S::kArmed, E::kDrivesLost, true, S::kLatched},
    {S::kArmed, E::kRearm, true, S::kArmed},
    {S::kRejoining, E::kCommandAccepted, true, S::kRejoining},
    {S::kRejoining, E::kCaughtUp, true, S::kFollowing},
    {S::kRejoining, E::kStale, true, S::kLatched},
    {S::kRejoining, E::kDrivesLost, true, S::kLatched},
    {S::kRejoining, E::kRearm, true, S::kRejoining},
    {S::kStartupHold, E::kStreamAhead, false, S::kStartupHold},  // holding: no stream to catch
    {S::kFollowing, E::kStreamAhead, true, S::kRejoining},
    {S::kLatched, E::kStreamAhead, false, S::kStartupHold},
    {S::kArmed, E::kStreamAhead, false, S::kStartupHold},
    {S::kRejoining, E::kStreamAhead, true, S::kRejoining},
};

TEST(BridgeState, EveryPairOfStateAndEventIsAsSpecified) {
  int checked = 0;
  std::set<std::pair<S, E>> pairs;
  for (const Expected& e : kSpec) {
    EXPECT_TRUE(pairs.insert({e.from, e.event}).second)
        << "the specification lists " << BridgeStateName(e.from) << " + " << BridgeEventName(e.event) << " twice";
    const BridgeTransition t = NextBridgeState(e.from, e.event);
    SCOPED_TRACE(std::string(BridgeStateName(e.from)) + " + " + BridgeEventName(e.event));
    EXPECT_EQ(t.allowed, e.allowed);
    if (e.allowed) {
      EXPECT_EQ(BridgeStateName(t.next), std::string(BridgeStateName(e.to)));
    }
    ++checked;
  }
  // As many distinct pairs as states × events: every pair, each once.
  EXPECT_EQ(checked, static_cast<int>(kStates.size() * kEvents.size())) << "the specification misses a pair";
  EXPECT_EQ(pairs.size(), kStates.size() * kEvents.size());
}

TEST(BridgeState, OnlyFollowingAndRejoiningMoveTheLegs) {
  for (const S s : kStates) {
    const bool moves = s == S::kFollowing || s == S::kRejoining;
    EXPECT_EQ(IsHolding(s), !moves) << BridgeStateName(s);
  }
}

// A running bridge, driven through every transition of the table.
class BridgeTour : public ::testing::Test {
 protected:
  static BridgeOptions Options() {
    BridgeOptions o;
    o.session_id = 9;
    return o;
  }
  leg_command_t Command(double dz_m) {
    Pose pose = model_.home_pose();
    pose.p_BoMo_B.z() += dz_m;
    const Vector6 lengths = model_.CompensatedLengths(pose, PrMode::kSigned);
    leg_command_t c{};
    c.utime = c.setpoint_utime = t_;
    c.seq = ++seq_;
    c.session_id = 9;
    for (int i = 0; i < kNumLegs; ++i) c.command_length_m[i] = lengths(i);
    return c;
  }
  bool Send(double dz_m) { return bridge_.HandleCommand(Command(dz_m), t_, &fault_); }
  void Cycles(int n) {
    for (int k = 0; k < n; ++k, t_ += 1000) bridge_.Cycle(t_, &state_, &fault_);
  }
  std::string State() const { return BridgeStateName(bridge_.state()); }

  PlatformModel model_{Huang2021Config()};
  RecordingBackend backend_;
  ActuatorBridge bridge_{model_, &backend_, Options()};
  std::int64_t t_ = 1000000000;
  std::int64_t seq_ = 0;
  fault_t fault_;
  leg_state_t state_;
};

TEST_F(BridgeTour, EveryTransitionIsTakenByARunningBridge) {
  EXPECT_EQ(State(), "startup-hold");
  backend_.answering = false;  // startup-hold + drives lost: still startup-hold
  Cycles(3);
  EXPECT_EQ(State(), "startup-hold");
  EXPECT_FALSE(Send(0.0)) << "refused while the drives are silent";
  backend_.answering = true;
  Cycles(1);
  ASSERT_TRUE(Send(0.0)) << fault_.reason;  // startup-hold + command
  EXPECT_EQ(State(), "following");
  Cycles(1);
  ASSERT_TRUE(Send(1e-5)) << fault_.reason;  // following + command
  EXPECT_EQ(State(), "following");
  EXPECT_TRUE(bridge_.Rearm());  // following + re-arm: nothing to do
  EXPECT_EQ(State(), "following");
  Cycles(60);  // following + stale
  EXPECT_EQ(State(), "latched");
  EXPECT_EQ(fault_.code, static_cast<std::int32_t>(FaultCode::kLatched));
  EXPECT_FALSE(Send(1e-5)) << "latched refuses a command, even one at the held position";
  EXPECT_EQ(State(), "latched");
  EXPECT_TRUE(bridge_.Rearm());  // latched + re-arm
  EXPECT_EQ(State(), "armed");
  Cycles(200);  // armed waits for its stream, however long
  EXPECT_EQ(State(), "armed");
  backend_.answering = false;  // armed + drives lost
  Cycles(1);
  EXPECT_EQ(State(), "latched");
  backend_.answering = true;
  Cycles(1);
  EXPECT_EQ(State(), "latched") << "drives that answer again do not unlatch";
  EXPECT_TRUE(bridge_.Rearm());
  ASSERT_TRUE(Send(0.01)) << fault_.reason;  // armed + command 10 mm away: rejoining
  EXPECT_EQ(State(), "rejoining");
  EXPECT_TRUE(bridge_.Rearm());  // rejoining + re-arm: nothing to do
  EXPECT_EQ(State(), "rejoining");
  Cycles(60);  // rejoining + stale
  EXPECT_EQ(State(), "latched");
  EXPECT_TRUE(bridge_.Rearm());
  ASSERT_TRUE(Send(0.01)) << fault_.reason;
  Cycles(1);
  backend_.answering = false;  // rejoining + drives lost
  Cycles(1);
  EXPECT_EQ(State(), "latched");
  backend_.answering = true;
  Cycles(1);
  EXPECT_TRUE(bridge_.Rearm());
  // Rejoin a stream standing still 10 mm away: caught up, then following.
  int commands = 0;
  for (; commands < 2000 && State() != "following"; ++commands) {
    ASSERT_TRUE(Send(0.01)) << fault_.reason;
    Cycles(1);
  }
  EXPECT_EQ(State(), "following");
  EXPECT_GT(commands, 10) << "caught up at once: the rejoin was not paced";
}

TEST_F(BridgeTour, ARestartedBridgeLeavesItsStartupHoldOnlyByAReArm) {
  ASSERT_FALSE(Send(0.05)) << "a stream 50 mm away is a jump";
  EXPECT_EQ(State(), "startup-hold");
  EXPECT_TRUE(bridge_.Rearm());  // startup-hold + re-arm
  EXPECT_EQ(State(), "armed");
  ASSERT_TRUE(Send(0.05)) << fault_.reason;
  EXPECT_EQ(State(), "rejoining");
}

// Each call a new request (a fresh id), stamped at `utime` by its sender.
arm_t Arm(std::int64_t session_id, std::int64_t utime) {
  static std::int64_t id = 0;
  arm_t arm{};
  arm.utime = utime;
  arm.seq = 1;
  arm.session_id = session_id;
  arm.request_id = ++id;
  arm.operator_name = "tester";
  return arm;
}

// EDSP_ARM as the bridge answers it (edsp-ctl waits for that reply).
TEST_F(BridgeTour, AnArmFromAnotherSessionIsIgnoredAndSaysSo) {
  ASSERT_TRUE(Send(0.0));
  Cycles(60);
  ASSERT_EQ(State(), "latched");
  const reply_t answer = bridge_.HandleArm(Arm(10, t_), t_).reply;
  EXPECT_EQ(answer.code, reply_t::CODE_OTHER_SESSION);
  EXPECT_EQ(answer.request_channel, "EDSP_ARM");
  EXPECT_NE(answer.reason.find("from session 10 ignored: this group is session 9"), std::string::npos) << answer.reason;
  EXPECT_EQ(State(), "latched");
}

TEST_F(BridgeTour, AnArmFromTheGroupReArmsALatchedBridgeAndConfirms) {
  ASSERT_TRUE(Send(0.0));
  const reply_t not_latched = bridge_.HandleArm(Arm(9, t_), t_).reply;
  EXPECT_EQ(not_latched.code, reply_t::CODE_DONE);
  EXPECT_NE(not_latched.reason.find("(was not latched)"), std::string::npos) << not_latched.reason;
  EXPECT_EQ(State(), "following");
  Cycles(60);
  const reply_t answer = bridge_.HandleArm(Arm(9, t_), t_).reply;
  EXPECT_EQ(answer.code, reply_t::CODE_DONE);
  EXPECT_EQ(answer.node, "actuator_bridge");
  EXPECT_NE(answer.reason.find("re-armed by tester; rejoining the command stream at 0.020 m/s"), std::string::npos)
      << answer.reason;
  EXPECT_EQ(State(), "armed");
}

// edsp-ctl sends its request again until it hears the reply: a copy of a
// re-arm is answered as the re-arm was (not "was not latched"), and nothing
// is re-armed twice; a late older request changes nothing.
TEST_F(BridgeTour, ACopyOfAReArmGetsTheSameAnswerAndReArmsNothingMore) {
  ASSERT_TRUE(Send(0.0));
  Cycles(60);
  ASSERT_EQ(State(), "latched");
  const arm_t older = Arm(9, t_ - 100000);
  const arm_t arm = Arm(9, t_);
  const auto answer = bridge_.HandleArm(arm, t_);
  ASSERT_TRUE(answer.acted);
  ASSERT_NE(answer.reply.reason.find("rejoining the command stream"), std::string::npos) << answer.reply.reason;
  const auto copy = bridge_.HandleArm(arm, t_ + 500000);
  EXPECT_FALSE(copy.acted);
  EXPECT_EQ(copy.reply.reason, answer.reply.reason);
  EXPECT_EQ(copy.reply.utime, answer.reply.utime);
  EXPECT_EQ(State(), "armed");
  const auto late = bridge_.HandleArm(older, t_ + 600000);
  EXPECT_EQ(late.reply.code, reply_t::CODE_STALE);
  EXPECT_NE(late.reply.reason.find("before the last one acted on"), std::string::npos) << late.reply.reason;
  EXPECT_EQ(State(), "armed");
}

TEST_F(BridgeTour, AnArmThatCannotResetTheDrivesLeavesTheBridgeLatchedAndSaysWhy) {
  ASSERT_TRUE(Send(0.0));
  Cycles(2);
  backend_.answering = false;
  backend_.resettable = false;
  Cycles(1);
  ASSERT_EQ(State(), "latched");
  const reply_t answer = bridge_.HandleArm(Arm(9, t_), t_).reply;
  EXPECT_EQ(answer.code, reply_t::CODE_FAILED);
  EXPECT_NE(answer.reason.find("fault 7500h"), std::string::npos) << answer.reason;
  EXPECT_EQ(State(), "latched");
}

}  // namespace bridge_state_table
}  // namespace edsp
