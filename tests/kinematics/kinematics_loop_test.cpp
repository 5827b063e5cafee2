// The kinematics node on a bus (memq://, in process): what edsp-kinematics
// publishes for what it receives, with the node's own logic underneath.
#include "edsp/kinematics/kinematics_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "edsp/kinematics/config.h"
#include "edsp/node/runtime.h"
#include "memq_bus.h"  // tests/support

namespace edsp {
namespace {

constexpr std::int64_t kSession = 9;

struct Fixture {
  explicit Fixture(bool replay = false) : loop(bus, node, Options(replay)) {
    bus.Subscribe<leg_command_t>("EDSP_LEG_COMMAND", [this](const leg_command_t& c) { commands.push_back(c); });
    bus.Subscribe<platform_state_t>("EDSP_PLATFORM_STATE", [this](const platform_state_t& s) { states.push_back(s); });
    bus.Subscribe<platform_config_t>("EDSP_CONFIG", [this](const platform_config_t& c) { configs.push_back(c); });
    bus.Subscribe<fault_t>("EDSP_FAULT", [this](const fault_t& f) { faults.push_back(f); });
    bus.Subscribe<reply_t>("EDSP_REPLY", [this](const reply_t& r) { replies.push_back(r); });
  }
  static KinematicsNodeOptions NodeOptions() {
    KinematicsNodeOptions o;
    o.session_id = kSession;
    return o;
  }
  static KinematicsLoopOptions Options(bool replay) {
    KinematicsLoopOptions o;
    o.config_text = "[geometry]\npreset = \"huang2021\"\n";
    o.replay = replay;
    return o;
  }
  void HandleAll() {
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }
  pose_setpoint_t Setpoint(double z_m, std::int64_t utime) const {
    pose_setpoint_t sp{};
    sp.utime = utime;
    sp.seq = 1;
    sp.session_id = kSession;
    const Vector6 home = node.model().home_pose().ToVector();
    for (int k = 0; k < 6; ++k) sp.pose[k] = home(k);
    sp.pose[2] += z_m;
    return sp;
  }

  Bus bus{test_support::MemqConfig("kinematics_loop")};
  KinematicsNode node{PlatformModel(Huang2021Config()), NodeOptions()};
  KinematicsLoop loop;
  std::vector<leg_command_t> commands;
  std::vector<platform_state_t> states;
  std::vector<platform_config_t> configs;
  std::vector<fault_t> faults;
  std::vector<reply_t> replies;
};

TEST(KinematicsLoop, ASetpointBecomesTheModelsCompensatedLegCommand) {
  Fixture f;
  const pose_setpoint_t sp = f.Setpoint(0.01, UtimeNow());
  f.bus.Publish("EDSP_SETPOINT", sp);
  f.HandleAll();
  ASSERT_EQ(f.commands.size(), 1u);
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = sp.pose[k];
  const Vector6 expected = f.node.model().CompensatedLengths(Pose::FromVector(q), PrMode::kSigned);
  for (int i = 0; i < kNumLegs; ++i) EXPECT_NEAR(f.commands[0].command_length_m[i], expected(i), 1e-12) << "leg " << i;
  EXPECT_EQ(f.commands[0].setpoint_utime, sp.utime);
}

TEST(KinematicsLoop, ASetpointItCannotValidateIsAFaultAndNeverForwarded) {
  Fixture f;
  pose_setpoint_t sp = f.Setpoint(0.0, UtimeNow());
  sp.pose[3] = std::nan("");
  f.bus.Publish("EDSP_SETPOINT", sp);
  f.HandleAll();
  EXPECT_TRUE(f.commands.empty());
  ASSERT_EQ(f.faults.size(), 1u);
  EXPECT_EQ(f.faults[0].code, static_cast<std::int32_t>(FaultCode::kNonFinite));
  EXPECT_EQ(f.faults[0].channel, "EDSP_SETPOINT");
}

// A replayed log's setpoints are seconds old by the wall clock: judged by
// their own stamps they reproduce the recorded commands, judged by the wall
// clock they are stale.
TEST(KinematicsLoop, AReplayJudgesSetpointsByTheirOwnClock) {
  const std::int64_t recorded = UtimeNow() - 10000000;
  Fixture live;
  live.bus.Publish("EDSP_SETPOINT", live.Setpoint(0.0, recorded));
  live.HandleAll();
  EXPECT_TRUE(live.commands.empty());
  ASSERT_EQ(live.faults.size(), 1u);
  EXPECT_EQ(live.faults[0].code, static_cast<std::int32_t>(FaultCode::kStale));

  Fixture replay(true);
  replay.bus.Publish("EDSP_SETPOINT", replay.Setpoint(0.0, recorded));
  replay.HandleAll();
  EXPECT_EQ(replay.commands.size(), 1u);
  EXPECT_TRUE(replay.faults.empty());
}

TEST(KinematicsLoop, EveryTenthLegStateBecomesAPlatformState) {
  Fixture f;
  const Pose pose = f.node.model().home_pose();
  const Vector6 encoders = f.node.model().EncoderLengths(pose);
  for (int n = 1; n <= 25; ++n) {
    leg_state_t legs{};
    legs.utime = UtimeNow();
    legs.seq = n;
    for (int i = 0; i < kNumLegs; ++i) legs.encoder_length_m[i] = encoders(i);
    f.bus.Publish("EDSP_LEG_STATE", legs);
  }
  f.HandleAll();
  ASSERT_EQ(f.states.size(), 2u) << "1 kHz in, 100 Hz out";
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(f.states[1].pose[k], pose.ToVector()(k), 1e-9);
}

TEST(KinematicsLoop, AnOperatorsPrModeRequestSwitchesTheModeAndIsConfirmed) {
  Fixture f;
  pr_mode_t request{};
  request.utime = UtimeNow();
  request.seq = 1;
  request.session_id = kSession;
  request.request_id = 11;
  request.pr_mode = leg_command_t::PR_NONE;
  request.operator_name = "tester";
  f.bus.Publish("EDSP_PR_MODE", request);
  f.HandleAll();
  EXPECT_EQ(f.node.pr_mode(), PrMode::kNone);
  ASSERT_EQ(f.replies.size(), 1u);
  EXPECT_EQ(f.replies[0].code, reply_t::CODE_DONE);
  EXPECT_EQ(f.replies[0].request_id, 11);
  EXPECT_EQ(f.replies[0].node, "kinematics");
  EXPECT_TRUE(f.faults.empty()) << "a request is answered on EDSP_REPLY, never confirmed as a fault";
}

// Live, a request stamped an hour ago (a log played onto a running group)
// switches nothing; replayed (--replay), it is judged by its own clock, as
// the log's setpoints are, and the operator's switch is made again.
TEST(KinematicsLoop, AnOldPrModeRequestIsStaleLiveAndTakenInAReplay) {
  pr_mode_t request{};
  request.utime = UtimeNow() - 3600 * 1000000LL;
  request.session_id = kSession;
  request.request_id = 13;
  request.pr_mode = leg_command_t::PR_NONE;
  request.operator_name = "tester";
  for (const bool replay : {false, true}) {
    Fixture f(replay);
    f.bus.Publish("EDSP_PR_MODE", request);
    f.HandleAll();
    ASSERT_EQ(f.replies.size(), 1u) << "replay " << replay;
    EXPECT_EQ(f.replies[0].code, replay ? reply_t::CODE_DONE : reply_t::CODE_STALE) << f.replies[0].reason;
    EXPECT_EQ(f.node.pr_mode(), replay ? PrMode::kNone : PrMode::kSigned);
  }
}

// EDSP_CALIBRATION carries the model file's text: the node switches to it
// (blended), confirms naming it, and the latched config then names it too.
TEST(KinematicsLoop, AnOperatorsCalibrationRequestSwitchesTheCalibrationAndIsConfirmed) {
  Fixture f;
  calibration_t request{};
  request.utime = UtimeNow();
  request.seq = 1;
  request.session_id = kSession;
  request.request_id = 12;
  request.operator_name = "tester";
  request.origin = "rig7.json";
  request.model_json = R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset",
      "verdict": "identified", "theta": [1e-4, 0, 0, 0, 0, 0]}]})";
  f.bus.Publish("EDSP_CALIBRATION", request);
  f.HandleAll();
  const calibration::CalibrationModel* in_force = f.node.calibration();
  ASSERT_NE(in_force, nullptr);
  EXPECT_EQ(in_force->origin, "rig7.json");
  ASSERT_EQ(f.replies.size(), 1u);
  EXPECT_EQ(f.replies[0].request_channel, "EDSP_CALIBRATION");
  EXPECT_EQ(f.replies[0].code, reply_t::CODE_DONE);
  EXPECT_TRUE(f.node.calibration_blending());  // from the next setpoint on
  f.loop.Poll(UtimeNow());
  f.HandleAll();
  ASSERT_FALSE(f.configs.empty());
  EXPECT_NE(f.configs.back().config_toml.find("switches the calibration: blending from none to rig7.json"),
            std::string::npos)
      << f.configs.back().config_toml;
}

TEST(KinematicsLoop, TheConfigIsPublishedOnceASecondWithTheFilesText) {
  Fixture f;
  const std::int64_t t0 = UtimeNow();
  f.loop.Poll(t0);
  f.loop.Poll(t0 + 500000);
  f.HandleAll();
  ASSERT_EQ(f.configs.size(), 1u);
  EXPECT_NE(f.configs[0].config_toml.find("huang2021"), std::string::npos);
  f.loop.Poll(t0 + 1000000);
  f.HandleAll();
  EXPECT_EQ(f.configs.size(), 2u);
}

}  // namespace
}  // namespace edsp
