// The kinematics node's logic: commands equal the model's compensated
// lengths, the PR mode switches live, bad setpoints become faults, encoder
// states become poses.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/kinematics_node.h"

namespace edsp {
namespace {

constexpr std::int64_t kNow = 2000000000;

KinematicsNode MakeNode(PrMode mode = PrMode::kSigned) {
  KinematicsNodeOptions options;
  options.session_id = 9;
  options.pr_mode = mode;
  return KinematicsNode(PlatformModel(Huang2021Config()), options);
}

pose_setpoint_t Setpoint(const Vector6& q) {
  pose_setpoint_t sp{};
  sp.utime = kNow - 1000;
  sp.seq = 17;
  sp.session_id = 9;
  for (int k = 0; k < 6; ++k) sp.pose[k] = q(k);
  return sp;
}

Vector6 SomePose() {
  Vector6 q;
  q << 0.1, -0.05, 1.6, 0.05, -0.1, 0.2;
  return q;
}

TEST(KinematicsNode, CommandIsTheCompensatedLengthAndItsMotorAngle) {
  KinematicsNode node = MakeNode();
  leg_command_t command;
  fault_t fault;
  ASSERT_TRUE(node.HandleSetpoint(Setpoint(SomePose()), kNow, &command, &fault)) << fault.reason;
  const PlatformModel& model = node.model();
  const Pose pose = Pose::FromVector(SomePose());
  const Vector6 expected = model.CompensatedLengths(pose, PrMode::kSigned);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_DOUBLE_EQ(command.command_length_m[i], expected(i));
    EXPECT_NEAR(model.LengthFromMotorAngle(i, command.motor_angle_rad[i]), expected(i), 1e-12);
    EXPECT_NEAR(command.ik_length_m[i] - command.pr_correction_m[i], command.command_length_m[i], 1e-15);
  }
  EXPECT_EQ(command.pr_mode, leg_command_t::PR_SIGNED);
  EXPECT_EQ(command.setpoint_seq, 17);
  EXPECT_EQ(command.session_id, 9);
}

// Each call a new request (a fresh id).
pr_mode_t ModeRequest(std::int8_t mode, std::int64_t utime, std::int64_t session_id = 9) {
  static std::int64_t id = 0;
  pr_mode_t r{};
  r.utime = utime;
  r.seq = 1;
  r.session_id = session_id;
  r.request_id = ++id;
  r.pr_mode = mode;
  r.operator_name = "tester";
  return r;
}

// EDSP_PR_MODE as the node answers it (edsp-ctl waits for that reply and
// resends until it comes): the switch made once, every copy answered alike
// (not "signed → signed"), a late older request refused without switching
// back, another session or an unknown mode refused with their codes.
TEST(KinematicsNode, PrModeRequestsAreConfirmedOnceAndCopiesChangeNothing) {
  KinematicsNode node = MakeNode(PrMode::kNone);
  const pr_mode_t to_signed = ModeRequest(leg_command_t::PR_SIGNED, kNow);
  const reply_t answer = node.HandlePrModeRequest(to_signed, kNow).reply;
  EXPECT_EQ(answer.code, reply_t::CODE_DONE);
  EXPECT_EQ(answer.request_channel, "EDSP_PR_MODE");
  EXPECT_NE(answer.reason.find("none → signed (requested by tester), blended over 500 ms"), std::string::npos)
      << answer.reason;
  EXPECT_EQ(node.pr_mode(), PrMode::kSigned);
  EXPECT_EQ(node.HandlePrModeRequest(to_signed, kNow + 500000).reply.reason, answer.reason);

  const pr_mode_t to_none = ModeRequest(leg_command_t::PR_NONE, kNow + 1000000);
  EXPECT_NE(node.HandlePrModeRequest(to_none, kNow + 1000000).reply.reason.find("signed → none"), std::string::npos);
  const reply_t late =
      node.HandlePrModeRequest(ModeRequest(leg_command_t::PR_SIGNED, kNow + 900000), kNow + 1100000).reply;
  EXPECT_EQ(late.code, reply_t::CODE_STALE);
  EXPECT_NE(late.reason.find("before the last one acted on"), std::string::npos) << late.reason;
  EXPECT_EQ(node.pr_mode(), PrMode::kNone);

  const reply_t foreign =
      node.HandlePrModeRequest(ModeRequest(leg_command_t::PR_SIGNED, kNow + 2000000, 10), kNow + 2000000).reply;
  EXPECT_EQ(foreign.code, reply_t::CODE_OTHER_SESSION);
  EXPECT_NE(foreign.reason.find("session 10 ignored: this group is session 9"), std::string::npos) << foreign.reason;
  const reply_t unknown = node.HandlePrModeRequest(ModeRequest(7, kNow + 3000000), kNow + 3000000).reply;
  EXPECT_EQ(unknown.code, reply_t::CODE_INVALID);
  EXPECT_NE(unknown.reason.find("PR mode 7 from tester is not 0..3; mode stays none"), std::string::npos)
      << unknown.reason;
  EXPECT_EQ(node.pr_mode(), PrMode::kNone);
}

// A live switch blends the correction linearly over 0.5 s of setpoint time
// from the old mode's to the new one's (no step for the bridge to refuse),
// and a switch mid-blend continues from where the correction is.
TEST(KinematicsNode, PrModeSwitchesLiveBlendingTheCorrection) {
  KinematicsNode node = MakeNode();
  fault_t fault;
  auto command_at = [&](std::int64_t dt_us) {
    pose_setpoint_t sp = Setpoint(SomePose());
    sp.utime = kNow + dt_us;
    leg_command_t c;
    EXPECT_TRUE(node.HandleSetpoint(sp, sp.utime, &c, &fault)) << fault.reason;
    return c;
  };
  const leg_command_t before = command_at(0);
  node.SwitchPrMode(PrMode::kNone);
  EXPECT_TRUE(node.blending());
  const leg_command_t start = command_at(1000);  // the blend starts here
  const leg_command_t quarter = command_at(1000 + 125000);
  const leg_command_t half = command_at(1000 + 250000);
  const leg_command_t done = command_at(1000 + 500000);
  EXPECT_FALSE(node.blending());
  EXPECT_EQ(start.pr_mode, leg_command_t::PR_NONE);
  for (int i = 0; i < kNumLegs; ++i) {
    const double s = before.pr_correction_m[i];
    EXPECT_NE(s, 0.0);
    EXPECT_NEAR(start.pr_correction_m[i], s, 1e-15);
    EXPECT_NEAR(quarter.pr_correction_m[i], 0.75 * s, 1e-15);
    EXPECT_NEAR(half.pr_correction_m[i], 0.5 * s, 1e-15);
    EXPECT_EQ(done.pr_correction_m[i], 0.0);
    EXPECT_NEAR(half.command_length_m[i], half.ik_length_m[i] - half.pr_correction_m[i], 1e-15);
  }
  // Back to signed, then to unsigned mid-way: the second blend starts from
  // the mix in force (half signed, half none), never with a step.
  node.SwitchPrMode(PrMode::kSigned);
  command_at(600000);
  const leg_command_t mid = command_at(600000 + 250000);
  node.SwitchPrMode(PrMode::kUnsigned);
  const leg_command_t next = command_at(600000 + 251000);
  const leg_command_t later = command_at(600000 + 251000 + 250000);
  node.SwitchPrMode(PrMode::kUnsigned);  // on the way there already: no restart
  const leg_command_t end = command_at(600000 + 251000 + 500000);
  const Vector6 unsigned_error =
      node.model().PrLengthError(node.model().Solve(Pose::FromVector(SomePose())), PrMode::kUnsigned);
  for (int i = 0; i < kNumLegs; ++i) {
    const double s = before.pr_correction_m[i];
    EXPECT_NEAR(mid.pr_correction_m[i], 0.5 * s, 1e-15);
    EXPECT_NEAR(next.pr_correction_m[i], 0.5 * s, 1e-15);  // continuous at the switch
    EXPECT_NEAR(later.pr_correction_m[i], 0.25 * s + 0.5 * unsigned_error(i), 1e-15);
    EXPECT_NEAR(end.pr_correction_m[i], unsigned_error(i), 1e-15);
  }
  EXPECT_FALSE(node.blending());
}

void ExpectRefused(pose_setpoint_t sp, FaultCode code, const std::string& fragment) {
  KinematicsNode node = MakeNode();
  leg_command_t command;
  fault_t fault;
  EXPECT_FALSE(node.HandleSetpoint(sp, kNow, &command, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(code)) << fault.reason;
  EXPECT_EQ(fault.channel, "EDSP_SETPOINT");
  EXPECT_EQ(fault.node, "kinematics");
  EXPECT_NE(fault.reason.find(fragment), std::string::npos) << fault.reason;
}

TEST(KinematicsNode, RefusesWhatItCannotValidate) {
  pose_setpoint_t sp = Setpoint(SomePose());
  sp.session_id = 8;
  ExpectRefused(sp, FaultCode::kForeignSession, "session 8");
  sp = Setpoint(SomePose());
  sp.pose[3] = std::nan("");
  ExpectRefused(sp, FaultCode::kNonFinite, "non-finite");
  sp = Setpoint(SomePose());
  sp.velocity[0] = INFINITY;
  ExpectRefused(sp, FaultCode::kNonFinite, "non-finite");
  sp = Setpoint(SomePose());
  sp.utime = kNow - 80000;
  ExpectRefused(sp, FaultCode::kStale, "80000 us old");
  sp = Setpoint(SomePose());
  sp.utime = kNow + 80000;  // the planner's host clock runs ahead of this one
  ExpectRefused(sp, FaultCode::kStale, "80000 us in the future");
  sp = Setpoint(SomePose());
  sp.pose[2] = 2.3;
  ExpectRefused(sp, FaultCode::kOutsideWorkspace, "leg_max_m");
}

TEST(KinematicsNode, EncoderLengthsBecomeThePose) {
  KinematicsNode node = MakeNode();
  const Pose truth = Pose::FromVector(SomePose());
  const Vector6 encoders = node.model().EncoderLengths(truth);
  leg_state_t legs{};
  legs.seq = 3;
  for (int i = 0; i < kNumLegs; ++i) legs.encoder_length_m[i] = encoders(i);
  platform_state_t state;
  fault_t fault;
  ASSERT_TRUE(node.HandleLegState(legs, kNow, &state, &fault)) << fault.reason;
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(state.pose[k], SomePose()(k), 1e-10);
  const Vector3 a = node.model().ObservationPoint(truth);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(state.observation_point_m[k], a(k), 1e-10);
  legs.encoder_length_m[4] = std::nan("");
  EXPECT_FALSE(node.HandleLegState(legs, kNow, &state, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kNonFinite));
  legs.encoder_length_m[4] = 9.0;  // no pose has this
  EXPECT_FALSE(node.HandleLegState(legs, kNow, &state, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kForwardKinematics));
}

TEST(KinematicsNode, ConfigMessageDescribesThePlatform) {
  KinematicsNode node = MakeNode();
  const platform_config_t c = node.ConfigMessage(kNow, "[geometry]\npreset = \"huang2021\"\n");
  EXPECT_EQ(c.preset, "huang2021");
  EXPECT_NEAR(c.base_joints_m[0][0], 0.876144, 5e-7);
  EXPECT_NEAR(c.platform_joints_m[0][1], 0.1, 1e-12);
  EXPECT_EQ(c.lead_m, 0.010);
  EXPECT_EQ(c.observation_point_m[0], 1.2);
  EXPECT_NE(c.config_toml.find("huang2021"), std::string::npos);
  EXPECT_EQ(c.config_toml.find("calibration"), std::string::npos);  // none in force
}

// The calibration in force (file, hash, what it applies) is latched with the
// config on EDSP_CONFIG, as a TOML comment that leaves the config readable.
TEST(KinematicsNode, ConfigMessageNamesTheCalibrationInForce) {
  KinematicsNodeOptions options;
  options.session_id = 9;
  const PlatformModel model(Huang2021Config());
  options.calibration = calibration::ParseCalibration(
      R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "verdict": "identified",
          "theta": [1e-5, 0, 0, 0, 0, 0]}]})",
      "rig7.json", model);
  KinematicsNode node(model, options);
  const std::string text = "[geometry]\npreset = \"huang2021\"\n";
  const platform_config_t c = node.ConfigMessage(kNow, text);
  EXPECT_NE(c.config_toml.find("# edsp-kinematics applies the calibration rig7.json (" + options.calibration->hash +
                               "): applies leg_offset"),
            std::string::npos)
      << c.config_toml;
  EXPECT_EQ(ParseConfig(c.config_toml, "EDSP_CONFIG").preset, "huang2021");
}

}  // namespace
}  // namespace edsp
