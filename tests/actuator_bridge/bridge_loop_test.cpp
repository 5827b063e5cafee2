// The bridge on a bus (memq://, in process): commands and re-arms in, leg
// states and faults out, the drive cycle on a clock the test owns.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/actuator_bridge/bridge_loop.h"

#include "edsp/reply_t.hpp"
#include "edsp/kinematics/config.h"
#include "counting_clock.h"  // tests/support
#include "memq_bus.h"
#include "recording_backend.h"

namespace edsp {
namespace {

using test_support::CountingClock;

struct LoopFixture {
  PlatformModel model{Huang2021Config()};
  RecordingBackend backend;
  ActuatorBridge bridge{model, &backend, Options()};
  Bus bus{test_support::MemqConfig("bridgeloop")};
  BridgeLoop loop{bus, bridge};
  std::vector<leg_state_t> states;
  std::vector<fault_t> faults;
  LoopFixture() {
    bus.Subscribe<leg_state_t>("EDSP_LEG_STATE", [this](const leg_state_t& s) { states.push_back(s); });
    bus.Subscribe<fault_t>("EDSP_FAULT", [this](const fault_t& f) { faults.push_back(f); });
    backend.exchanges.clear();
  }
  static BridgeOptions Options() {
    BridgeOptions o;
    o.session_id = 5;
    return o;
  }
  leg_command_t Command(double dz_m, std::int64_t seq) const {
    Pose pose = model.home_pose();
    pose.p_BoMo_B.z() += dz_m;
    const Vector6 lengths = model.CompensatedLengths(pose, PrMode::kSigned);
    leg_command_t c{};
    c.utime = UtimeNow();
    c.setpoint_utime = c.utime - 100;  // planned 100 µs before it left the kinematics
    c.seq = seq;
    c.session_id = 5;
    for (int i = 0; i < kNumLegs; ++i) c.command_length_m[i] = lengths(i);
    return c;
  }
};

TEST(BridgeLoop, ACommandOnTheBusReachesTheDrivesAtTheNextCycleAndIsReportedAsALegState) {
  LoopFixture f;
  const leg_command_t c = f.Command(1e-5, 1);
  f.bus.Publish("EDSP_LEG_COMMAND", c);
  EXPECT_GE(f.bus.Handle(std::chrono::milliseconds(100)), 1);
  EXPECT_EQ(f.backend.exchanges, "") << "a command touches no drive before the cycle";
  f.loop.RunCycle(UtimeNow(), 0);
  EXPECT_EQ(f.backend.exchanges, "RW");
  EXPECT_NEAR(f.backend.written.motor_angle_rad[0], f.model.MotorAngleFromLength(0, c.command_length_m[0]), 1e-12);
  f.loop.RunCycle(UtimeNow(), 0);  // reads (first) where the last cycle's write took the drives
  f.bus.Handle(std::chrono::milliseconds(100));
  ASSERT_EQ(f.states.size(), 2u);
  EXPECT_EQ(f.states[1].command_seq, 1);
  EXPECT_NEAR(f.states[1].encoder_length_m[0], c.command_length_m[0], 1e-12);
  // Both latencies seen: arrival ≥ 100 µs, the write no earlier than the arrival.
  const LatencySummary arrival = f.loop.arrival_latency().Summarize();
  const LatencySummary written = f.loop.write_latency().Summarize();
  ASSERT_EQ(arrival.samples, 1);
  ASSERT_EQ(written.samples, 1);
  EXPECT_GE(arrival.max_us, 100.0);
  EXPECT_GE(written.max_us, arrival.max_us);
  const nlohmann::json report = LatencyReport(f.loop, 3);
  EXPECT_EQ(report.at("samples").get<int>(), 1);
  EXPECT_EQ(report.at("to_drives").at("samples").get<int>(), 1);
  EXPECT_EQ(report.at("deadline_misses").get<int>(), 3);
}

TEST(BridgeLoop, ALatchedBridgeIsReArmedOverEdspArmAndAnswersOnEdspReply) {
  LoopFixture f;
  std::vector<reply_t> replies;
  f.bus.Subscribe<reply_t>("EDSP_REPLY", [&](const reply_t& r) { replies.push_back(r); });
  f.bus.Publish("EDSP_LEG_COMMAND", f.Command(0.0, 1));
  f.bus.Handle(std::chrono::milliseconds(100));
  const std::int64_t t = UtimeNow();
  for (int k = 0; k < 60; ++k) f.loop.RunCycle(t + k * 1000, 0);  // 60 ms without a command
  ASSERT_TRUE(f.bridge.latched());
  const std::size_t faults_before = f.faults.size();
  arm_t arm{};
  arm.utime = UtimeNow();
  arm.seq = 1;
  arm.session_id = 5;
  arm.request_id = 99;
  arm.operator_name = "test";
  f.bus.Publish("EDSP_ARM", arm);
  for (int k = 0; k < 3 && f.bridge.latched(); ++k) f.bus.Handle(std::chrono::milliseconds(100));
  EXPECT_FALSE(f.bridge.latched());
  f.bus.Handle(std::chrono::milliseconds(10));
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].request_id, 99);
  EXPECT_EQ(replies[0].code, reply_t::CODE_DONE);
  EXPECT_NE(replies[0].reason.find("re-armed by test"), std::string::npos) << replies[0].reason;
  for (std::size_t k = faults_before; k < f.faults.size(); ++k) {
    EXPECT_EQ(f.faults[k].reason.find("re-armed by"), std::string::npos)
        << "confirmed as a fault: " << f.faults[k].reason;
  }
}

// Every cycle overran (the clock never leaves time to wait in): the
// commands that came are still taken, cycle by cycle, not left in the
// socket until the bridge latches on a stream that is there.
TEST(BridgeLoop, ABridgeWhoseCyclesOverrunStillTakesItsCommands) {
  LoopFixture f;
  f.bus.Publish("EDSP_LEG_COMMAND", f.Command(1e-5, 1));
  CountingClock clock(3);
  f.loop.Run(clock, [&] { return clock.done(); });
  f.bus.Handle(std::chrono::milliseconds(100));
  ASSERT_EQ(f.states.size(), 3u);
  EXPECT_EQ(f.states.back().command_seq, 1);
  EXPECT_FALSE(f.bridge.holding());
}

TEST(BridgeLoop, RunTicksOnTheClockItIsGivenOneExchangePerTick) {
  LoopFixture f;
  CountingClock clock(25);
  f.loop.Run(clock, [&] { return clock.done(); });
  std::string expected;
  for (int k = 0; k < 25; ++k) expected += "RW";
  EXPECT_EQ(f.backend.exchanges, expected);
  f.bus.Handle(std::chrono::milliseconds(100));
  EXPECT_EQ(f.states.size(), 25u);
}

TEST(RateClock, TicksFallOnTheHostsGridShiftedByThePhase) {
  EXPECT_EQ(NextGridTick(5'000'100, 1'000'000, 400'000), 5'400'000);
  EXPECT_EQ(NextGridTick(5'400'000, 1'000'000, 400'000), 6'400'000);  // strictly after
  EXPECT_EQ(NextGridTick(5'399'999, 1'000'000, 400'000), 5'400'000);
  EXPECT_EQ(NextGridTick(5'000'000, 1'000'000, 0), 6'000'000);
  EXPECT_EQ(NextGridTick(5'000'000, 1'000'000, 1'400'000), 5'400'000);  // the phase modulo the period
}

}  // namespace
}  // namespace edsp
