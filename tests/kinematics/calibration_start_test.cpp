// A calibration in force when the kinematics node starts: its first command
// is where the drives hold (a fresh rig at the nominal model's command; a
// restarted node's drives already carrying the calibration), and the
// correction blends in from there, its fastest leg at 5% of the legs' speed
// limit, whatever its size at home. Held to a node that ran the
// calibration from its first command and to one without it. A calibration
// that would put a leg beyond its stroke at home is refused when loaded.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "calibrated_node.h"
#include "edsp/kinematics/kinematics_node.h"
#include "platform_models.h"

namespace edsp {
namespace {

constexpr std::int64_t kStart = 2000000000;
constexpr std::int64_t kBlendUs = 200000;  // a switch's: not the start's

// Leg offsets of millimetres, as whole rigs' offsets and joint centres add
// up to at home: one cycle of such a step is far past the bridge's jump.
calibration::CalibrationModel Millimetres() {
  return calibration::ParseCalibration(
      R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "verdict": "identified",
          "theta": [4e-3, -3e-3, 2.5e-3, -1e-3, 3.5e-3, -4.5e-3]}]})",
      "whole-rig.json", test_support::Huang2021Model());
}

KinematicsNode MakeNode(std::optional<calibration::CalibrationModel> calibration, bool from_drives = true) {
  return test_support::CalibratedNode(
      std::move(calibration), kBlendUs,
      from_drives ? test_support::CalibrationStart::kFromTheDrives : test_support::CalibrationStart::kInForceAtOnce);
}

// Cycle k at home, held: the start of every session.
pose_setpoint_t AtHome(int k) {
  pose_setpoint_t sp{};
  sp.utime = kStart + 1000 * k;
  sp.seq = k + 1;
  sp.session_id = 9;
  const Vector6 home = test_support::Huang2021Model().home_pose().ToVector();
  for (int i = 0; i < 6; ++i) sp.pose[i] = home(i);
  return sp;
}

Vector6 Command(KinematicsNode& node, int k) {
  const leg_command_t c = test_support::CommandFor(node, AtHome(k));
  Vector6 out;
  for (int i = 0; i < 6; ++i) out(i) = c.command_length_m[i];
  return out;
}

leg_state_t DrivesAt(const Vector6& lengths_m) {
  leg_state_t legs{};
  for (int i = 0; i < 6; ++i) legs.encoder_length_m[i] = lengths_m(i);
  return legs;
}

TEST(CalibrationStart, FromDrivesAtTheNominalCommandItBlendsInWithoutAStep) {
  KinematicsNode without = MakeNode(std::nullopt), in_force = MakeNode(Millimetres(), false),
                 node = MakeNode(Millimetres());
  const Vector6 nominal = Command(without, 0), calibrated = Command(in_force, 0);
  const double correction = (calibrated - nominal).cwiseAbs().maxCoeff();
  ASSERT_GT(correction, 4e-3);  // the model's 4.5 mm
  node.NoteDrives(DrivesAt(nominal));
  EXPECT_LT((Command(node, 0) - nominal).cwiseAbs().maxCoeff(), 1e-12) << "the first command is where they hold";
  EXPECT_TRUE(node.calibration_blending());
  // Its fastest leg at 5% of the legs' speed limit, a cycle at a time.
  const double pace_m_per_cycle = 0.05 * test_support::Huang2021Model().config().limits.leg_speed_max_m_s * 1e-3;
  const int blend_cycles = static_cast<int>(std::ceil(correction / pace_m_per_cycle));
  Vector6 previous = nominal;
  double largest_step = 0.0;
  int k = 1;
  for (; node.calibration_blending() && k < 10 * blend_cycles; ++k) {
    const Vector6 now = Command(node, k);
    largest_step = std::max(largest_step, (now - previous).cwiseAbs().maxCoeff());
    previous = now;
  }
  EXPECT_LT(largest_step, 1.01 * pace_m_per_cycle);
  EXPECT_NEAR(k, blend_cycles, 2) << "blended in within what that pace takes";
  EXPECT_LT((Command(node, k) - calibrated).cwiseAbs().maxCoeff(), 1e-12) << "then the calibration in force";
}

TEST(CalibrationStart, ARestartedNodeWhoseDrivesCarryItCommandsItAtOnce) {
  KinematicsNode in_force = MakeNode(Millimetres(), false), node = MakeNode(Millimetres());
  const Vector6 calibrated = Command(in_force, 0);
  node.NoteDrives(DrivesAt(calibrated));
  EXPECT_LT((Command(node, 0) - calibrated).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(node.calibration_blending());
}

TEST(CalibrationStart, DrivesPartwayStartItPartway) {
  KinematicsNode without = MakeNode(std::nullopt), in_force = MakeNode(Millimetres(), false),
                 node = MakeNode(Millimetres());
  const Vector6 nominal = Command(without, 0), calibrated = Command(in_force, 0);
  const Vector6 partway = nominal + 0.3 * (calibrated - nominal);
  node.NoteDrives(DrivesAt(partway));
  EXPECT_LT((Command(node, 0) - partway).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NE(node.DescribeCalibration().find("blending from none to whole-rig.json"), std::string::npos)
      << node.DescribeCalibration();
  EXPECT_NE(node.DescribeCalibration().find("(30% of 180 ms)"), std::string::npos)
      << node.DescribeCalibration() << ": 4.5 mm at 25 mm/s";
}

// A switch before the first command: the model it names is the one that
// starts from the drives (none: the nominal command at once), never a blend
// from a model the drives never carried.
TEST(CalibrationStart, ASwitchBeforeTheFirstCommandStartsFromTheDrivesToo) {
  KinematicsNode without = MakeNode(std::nullopt);
  const Vector6 nominal = Command(without, 0);
  for (const bool off : {true, false}) {
    KinematicsNode node = MakeNode(Millimetres());
    node.NoteDrives(DrivesAt(nominal));
    std::string why_not;
    ASSERT_TRUE(node.SwitchCalibration(off ? std::nullopt : std::optional(Millimetres()), &why_not)) << why_not;
    Vector6 previous = Command(node, 0);
    EXPECT_LT((previous - nominal).cwiseAbs().maxCoeff(), 1e-12) << (off ? "off" : "again");
    double largest_step = 0.0;
    for (int k = 1; k < 400; ++k) {
      const Vector6 now = Command(node, k);
      largest_step = std::max(largest_step, (now - previous).cwiseAbs().maxCoeff());
      previous = now;
    }
    EXPECT_LT(largest_step, 30e-6) << (off ? "off" : "again") << ": 25 um a cycle at most";
  }
}

TEST(CalibrationStart, BeforeAnyReadingOfTheDrivesNothingIsForwarded) {
  KinematicsNode node = MakeNode(Millimetres());
  leg_command_t c;
  fault_t fault;
  const pose_setpoint_t sp = AtHome(0);
  EXPECT_FALSE(node.HandleSetpoint(sp, sp.utime, &c, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kStale));
  EXPECT_NE(fault.reason.find("no reading of the drives yet"), std::string::npos) << fault.reason;
}

TEST(CalibrationStart, ACorrectionBeyondALegsStrokeAtHomeIsRefusedWhenLoaded) {
  PlatformConfig tight = Huang2021Config();
  const PlatformModel model(tight);
  const Vector6 home_legs = model.Solve(model.home_pose()).length_m;
  tight.limits.leg_max_m = home_legs.maxCoeff() + 2e-3;  // 2 mm of stroke left above home
  try {
    calibration::ParseCalibration(
        R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "verdict": "identified",
            "theta": [-5e-3, -5e-3, -5e-3, -5e-3, -5e-3, -5e-3]}]})",
        "long.json", PlatformModel(tight));
    FAIL() << "a calibration 3 mm past the stroke was taken";
  } catch (const calibration::CalibrationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("long.json: leg "), std::string::npos) << what;
    EXPECT_NE(what.find("a correction of 0.005000 m"), std::string::npos) << what;
    EXPECT_NE(what.find("outside its stroke"), std::string::npos) << what;
  }
  // The same model on the platform as it is: taken.
  EXPECT_NO_THROW(calibration::ParseCalibration(
      R"({"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "verdict": "identified",
          "theta": [-5e-3, -5e-3, -5e-3, -5e-3, -5e-3, -5e-3]}]})",
      "long.json", model));
}

}  // namespace
}  // namespace edsp
