// A calibration switched while the platform moves (EDSP_CALIBRATION,
// `edsp-ctl calibration`): the command goes from the old calibration's to
// the new one's linearly over the blend, checked cycle by cycle against
// two nodes that ran each calibration from the start (no step, and after
// the blend exactly the new calibration); requests the node must refuse
// are refused naming why, and leave the calibration in force untouched.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "calibrated_node.h"
#include "edsp/kinematics/kinematics_node.h"
#include "platform_models.h"

namespace edsp {
// Named, not anonymous: its helpers share names with other tests of its binary.
namespace calibration_switch {

constexpr std::int64_t kSwitchStart = 2000000000;
constexpr std::int64_t kSwitchBlendUs = 200000;

// Leg offsets and lead errors: corrections that depend on the pose only, so
// a compensator started mid-run agrees with one that ran from the start.
const char kModelJson[] = R"({"format": "edsp-gap-model/1", "effects": [
    {"name": "leg_offset", "verdict": "identified", "theta": [2e-4, -1.5e-4, 1e-4, -2.5e-4, 1.2e-4, -0.5e-4]},
    {"name": "lead_error", "verdict": "identified", "theta": [1.5e-4, -1e-4, 2e-4, 0.5e-4, -1.5e-4, 1e-4]}]})";

calibration::CalibrationModel Model() {
  return calibration::ParseCalibration(kModelJson, "rig7.json", test_support::Huang2021Model());
}

// A node with `calibration` in force from its first command: the reference
// the switches are held to (how a calibration in force at start blends in
// from the drives is calibration_start_test's).
KinematicsNode MakeNode(std::optional<calibration::CalibrationModel> calibration) {
  return test_support::CalibratedNode(std::move(calibration), kSwitchBlendUs,
                                      test_support::CalibrationStart::kInForceAtOnce);
}

// Cycle k of a move up along z at 0.1 m/s, 1 kHz.
pose_setpoint_t Setpoint(int k) {
  pose_setpoint_t sp{};
  sp.utime = kSwitchStart + 1000 * k;
  sp.seq = k + 1;
  sp.session_id = 9;
  const double pose[6] = {0.05, -0.02, 1.45 + 1e-4 * k, 0.02, -0.03, 0.1};
  std::copy(pose, pose + 6, sp.pose);
  sp.velocity[2] = 0.1;
  return sp;
}

leg_command_t SwitchCommand(KinematicsNode& node, int k) { return test_support::CommandFor(node, Setpoint(k)); }

// Each call a new request (a fresh id).
calibration_t Request(const std::string& json, std::int64_t utime, std::int64_t session_id = 9) {
  static std::int64_t id = 0;
  calibration_t r{};
  r.request_id = ++id;
  r.utime = utime;
  r.seq = 1;
  r.session_id = session_id;
  r.operator_name = "tester";
  r.origin = json.empty() ? "off" : "rig7.json";
  r.model_json = json;
  return r;
}

// Runs `node` for cycles [0, n) beside one without and one with the model
// from the start, switching it by `request` before cycle `at`; checks
// every command against the blend of the two (within 1 nm: a compensator
// started mid-motion evaluates its first cycle at the nominal stroke, the
// one running from the start at the corrected one) and returns the largest
// per-cycle change of the switched node's correction.
double RunSwitch(KinematicsNode& node, bool to_calibrated, int at, int n, const calibration_t& request) {
  KinematicsNode without = MakeNode(std::nullopt), with = MakeNode(Model());
  double largest_change = 0.0;
  std::array<double, kNumLegs> last_correction{};  // switched − nominal, the cycle before
  for (int k = 0; k < n; ++k) {
    if (k == at) {
      const reply_t answer = node.HandleCalibrationRequest(request, Setpoint(k).utime).reply;
      EXPECT_EQ(answer.code, reply_t::CODE_DONE) << answer.reason;
      EXPECT_TRUE(node.calibration_blending());
    }
    const leg_command_t c = SwitchCommand(node, k), a = SwitchCommand(without, k), b = SwitchCommand(with, k);
    // The blend advances by the setpoint time since the last setpoint: the
    // first setpoint after the request carries one cycle of it.
    const double w = k < at ? 0.0 : std::min(1.0, (k - at + 1) * 1000.0 / kSwitchBlendUs);
    const double weight_new = to_calibrated ? w : 1.0 - w;
    for (int i = 0; i < kNumLegs; ++i) {
      const double expected = (1.0 - weight_new) * a.command_length_m[i] + weight_new * b.command_length_m[i];
      EXPECT_NEAR(c.command_length_m[i], expected, 1e-9) << "cycle " << k << " leg " << i;
      const double correction = c.command_length_m[i] - a.command_length_m[i];
      const auto leg = static_cast<std::size_t>(i);
      if (k > 0) largest_change = std::max(largest_change, std::abs(correction - last_correction[leg]));
      last_correction[leg] = correction;
    }
  }
  return largest_change;
}

TEST(CalibrationSwitch, ACalibrationSwitchedOnMidMotionBlendsIntoItWithoutAStep) {
  KinematicsNode node = MakeNode(std::nullopt);
  const double largest = RunSwitch(node, true, 100, 400, Request(kModelJson, kSwitchStart));
  EXPECT_FALSE(node.calibration_blending());
  const calibration::CalibrationModel* in_force = node.calibration();
  ASSERT_NE(in_force, nullptr);
  EXPECT_EQ(in_force->origin, "rig7.json");
  // The whole correction (up to 0.25 mm) would be one step unblended; over
  // 200 cycles each is at most 1/200 of it.
  EXPECT_LT(largest, 0.3e-3 / 200.0);
  EXPECT_GT(largest, 0.1e-3 / 200.0);  // and the blend did move it
}

TEST(CalibrationSwitch, SwitchedOffItBlendsBackToTheNominalModel) {
  KinematicsNode node = MakeNode(Model());
  const double largest = RunSwitch(node, false, 100, 400, Request("", kSwitchStart));
  EXPECT_EQ(node.calibration(), nullptr);
  EXPECT_LT(largest, 0.3e-3 / 200.0);
}

// Point A as `node` estimates it from the encoder lengths `lengths`.
Vector3 EstimatedA(KinematicsNode& node, const leg_command_t& lengths) {
  leg_state_t legs{};
  for (int i = 0; i < kNumLegs; ++i) legs.encoder_length_m[i] = lengths.command_length_m[i];
  platform_state_t state;
  fault_t fault;
  EXPECT_TRUE(node.HandleLegState(legs, kSwitchStart, &state, &fault)) << fault.reason;
  return Vector3(state.observation_point_m[0], state.observation_point_m[1], state.observation_point_m[2]);
}

// The forward kinematics on EDSP_PLATFORM_STATE blends with the commands:
// half-way, the same encoders give a point A half-way between the nominal
// node's and the calibrated node's (µm changes: linear to 1%); after the
// blend, the calibrated node's.
TEST(CalibrationSwitch, ForwardKinematicsBlendsWithTheSwitch) {
  KinematicsNode node = MakeNode(std::nullopt), with = MakeNode(Model()), without = MakeNode(std::nullopt);
  ASSERT_EQ(node.HandleCalibrationRequest(Request(kModelJson, kSwitchStart), kSwitchStart).reply.code,
            reply_t::CODE_DONE);
  for (int k = 0; k <= 100; ++k)
    SwitchCommand(node, k), SwitchCommand(with, k), SwitchCommand(without, k);  // 100 of 200 ms
  const leg_command_t encoders = SwitchCommand(without, 101);
  SwitchCommand(node, 101), SwitchCommand(with, 101);  // 101 ms: w = 0.505
  const Vector3 nominal = EstimatedA(without, encoders), calibrated = EstimatedA(with, encoders);
  ASSERT_GT((calibrated - nominal).norm(), 1e-5);  // the calibration does change the estimate
  const Vector3 half_way = EstimatedA(node, encoders);
  EXPECT_NEAR((half_way - nominal).norm() / (calibrated - nominal).norm(), 0.505, 0.01);
  for (int k = 102; k < 250; ++k) SwitchCommand(node, k), SwitchCommand(with, k);
  EXPECT_LT((EstimatedA(node, encoders) - EstimatedA(with, encoders)).norm(), 1e-9);
}

// Setpoint stamps are the sender's word: a stream that goes back in time,
// jumps ahead (a replayed log, a late planner) or sits at the int64 limits
// moves the blend by at most 10 ms of it per setpoint, never back, and
// never overflows (the sanitized build checks that).
TEST(CalibrationSwitch, JumpsInSetpointTimeNeverJumpTheCorrection) {
  KinematicsNode node = MakeNode(std::nullopt), without = MakeNode(std::nullopt), with = MakeNode(Model());
  ASSERT_EQ(node.HandleCalibrationRequest(Request(kModelJson, kSwitchStart), kSwitchStart).reply.code,
            reply_t::CODE_DONE);
  const std::int64_t stamps[] = {kSwitchStart,
                                 kSwitchStart + 1000,
                                 kSwitchStart - 40000,
                                 kSwitchStart + 5000000,
                                 kSwitchStart + 5001000,
                                 INT64_MIN + 1,
                                 INT64_MAX,
                                 INT64_MAX,
                                 kSwitchStart};
  double last_weight = 0.0;
  for (std::int64_t stamp : stamps) {
    pose_setpoint_t sp = Setpoint(3);
    sp.utime = stamp;
    leg_command_t c, a, b;
    fault_t fault;
    ASSERT_TRUE(node.HandleSetpoint(sp, stamp, &c, &fault)) << fault.reason;  // judged by its own clock (replay)
    ASSERT_TRUE(without.HandleSetpoint(sp, stamp, &a, &fault)) << fault.reason;
    ASSERT_TRUE(with.HandleSetpoint(sp, stamp, &b, &fault)) << fault.reason;
    const double weight =
        (c.command_length_m[3] - a.command_length_m[3]) / (b.command_length_m[3] - a.command_length_m[3]);
    EXPECT_GE(weight, last_weight - 1e-9) << "stamp " << stamp;
    EXPECT_LE(weight - last_weight, calibration::CalibrationBlend::kMaxAdvance_us / kSwitchBlendUs + 1e-9)
        << "stamp " << stamp;
    last_weight = weight;
  }
  EXPECT_GT(last_weight, 0.0);
}

std::string Answer(KinematicsNode& node, const calibration_t& request) {
  return node.HandleCalibrationRequest(request, request.utime).reply.reason;
}

// The confirmation names what is switched from and to (file, hash,
// effects); every copy of the request gets the same answer and switches
// nothing; what cannot be applied is refused with the reason, and the
// calibration in force stays.
TEST(CalibrationSwitch, RequestsAreConfirmedNamingTheModelOrRefusedNamingWhy) {
  KinematicsNode node = MakeNode(std::nullopt);
  const calibration_t on = Request(kModelJson, kSwitchStart);
  const reply_t confirmed = node.HandleCalibrationRequest(on, kSwitchStart).reply;
  EXPECT_EQ(confirmed.code, reply_t::CODE_DONE);
  EXPECT_EQ(confirmed.request_channel, "EDSP_CALIBRATION");
  EXPECT_NE(confirmed.reason.find("calibration none → rig7.json (" + Model().hash +
                                  "): applies leg_offset, lead_error (requested by tester), blended over 200 ms"),
            std::string::npos)
      << confirmed.reason;
  EXPECT_EQ(Answer(node, on), confirmed.reason);  // a copy: answered alike, not switched again
  EXPECT_TRUE(node.calibration_blending());

  // While the blend runs, another switch waits.
  for (int k = 0; k < 50; ++k) SwitchCommand(node, k);
  const std::string busy = Answer(node, Request("", kSwitchStart + 100000));
  EXPECT_NE(busy.find("still blending (151 of 200 ms"), std::string::npos) << busy;
  for (int k = 50; k < 250; ++k) SwitchCommand(node, k);
  EXPECT_FALSE(node.calibration_blending());

  // A refusal holds nothing back: another session's request stamped later
  // than the next genuine one does not make that one "older".
  KinematicsNode fresh = MakeNode(std::nullopt);
  EXPECT_NE(Answer(fresh, Request("", kSwitchStart + 2000000, 4)).find("from session 4"), std::string::npos);
  EXPECT_EQ(fresh.HandleCalibrationRequest(Request(kModelJson, kSwitchStart + 1000000), kSwitchStart).reply.code,
            reply_t::CODE_DONE);

  const std::string in_force = "in force stays rig7.json (" + Model().hash + ")";
  const std::string other_session = Answer(node, Request("", kSwitchStart + 300000, 4));
  EXPECT_NE(other_session.find("from session 4 ignored: this group is session 9"), std::string::npos) << other_session;
  EXPECT_NE(other_session.find(in_force), std::string::npos) << other_session;
  const std::string not_json = Answer(node, Request("{", kSwitchStart + 400000));
  EXPECT_NE(not_json.find("rig7.json: not JSON"), std::string::npos) << not_json;
  const std::string absurd = Answer(
      node, Request(R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "theta": [0.05,0,0,0,0,0]}]})",
                    kSwitchStart + 500000));
  EXPECT_NE(absurd.find("theta[0] = 0.05"), std::string::npos) << absurd;
  const std::string elsewhere =
      Answer(node, Request(R"({"format": "edsp-gap-model/1", "platform": "home_length_m=2,2,2,2,2,2", "effects": []})",
                           kSwitchStart + 600000));
  EXPECT_NE(elsewhere.find("another platform"), std::string::npos) << elsewhere;
  const std::string late = Answer(node, Request("", kSwitchStart - 1));
  EXPECT_NE(late.find("before the last one acted on"), std::string::npos) << late;
  EXPECT_FALSE(node.calibration_blending());
  const calibration::CalibrationModel* kept = node.calibration();
  ASSERT_NE(kept, nullptr);
  EXPECT_EQ(kept->hash, Model().hash);
}

// `ambiguous` effects are applied only when the request says so, as with
// --apply-ambiguous at start-up.
TEST(CalibrationSwitch, AmbiguousEffectsAreAppliedOnlyWhenTheRequestAsks) {
  const std::string json = R"({"format": "edsp-gap-model/1", "effects": [
      {"name": "leg_offset", "verdict": "ambiguous", "theta": [1e-4, 0, 0, 0, 0, 0]}]})";
  KinematicsNode strict = MakeNode(std::nullopt), lenient = MakeNode(std::nullopt);
  calibration_t request = Request(json, kSwitchStart);
  EXPECT_NE(Answer(strict, request).find("not applied: leg_offset (ambiguous)"), std::string::npos);
  request.apply_ambiguous = 1;
  EXPECT_NE(Answer(lenient, request).find("applies leg_offset"), std::string::npos);
  const calibration::CalibrationModel *held_back = strict.calibration(), *applied = lenient.calibration();
  ASSERT_TRUE(held_back != nullptr && applied != nullptr);
  EXPECT_TRUE(held_back->applied.empty());
  EXPECT_EQ(applied->applied.size(), 1u);
}

}  // namespace calibration_switch
}  // namespace edsp
