// Config loading: the repo's file, overrides, and every error path names the
// file, the key and the value.
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "thrown_message.h"

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

const char* const kPreset = "[geometry]\npreset = \"huang2021\"\n";

// Explicit arrays equal to the preset's, as TOML rows.
std::string Rows(const Matrix36& m) {
  std::string out = "[";
  for (int i = 0; i < kNumLegs; ++i) {
    out += fmt::format("[{:.17g}, {:.17g}, {:.17g}]{}", m(0, i), m(1, i), m(2, i), i + 1 < kNumLegs ? ", " : "]");
  }
  return out;
}

std::string ExplicitGeometry(const PlatformGeometry& g) {
  return fmt::format(
      "[geometry]\nhome_height_m = {}\nbase_joints_m = {}\nplatform_joints_m = {}\n"
      "base_axes = {}\nplatform_axes = {}\n[observation]\npoint_m = [1.2, 0, 0]\n",
      g.home_height_m, Rows(g.p_BoBi_B), Rows(g.p_MoPi_M), Rows(g.ja_B), Rows(g.jd_M));
}

// Parses `text` and returns the ConfigError message ("" if none was thrown).
std::string ErrorOf(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseConfig(text, "rig.toml"); });
}

#define EXPECT_CONFIG_ERROR(text, ...)                                                                     \
  do {                                                                                                     \
    const std::string message = ErrorOf(text);                                                             \
    ASSERT_FALSE(message.empty()) << "accepted:\n" << (text);                                              \
    EXPECT_NE(message.find("rig.toml"), std::string::npos) << message;                                     \
    for (const char* part : {__VA_ARGS__}) {                                                               \
      EXPECT_NE(message.find(part), std::string::npos) << "message lacks \"" << part << "\": " << message; \
    }                                                                                                      \
  } while (0)

TEST(Config, RepositoryFileIsThePresetWithItsDefaults) {
  const PlatformConfig file = LoadConfigFile(SourcePath("config/huang2021.toml"));
  const PlatformConfig preset = Huang2021Config();
  EXPECT_TRUE(file.geometry.p_BoBi_B.isApprox(preset.geometry.p_BoBi_B));
  EXPECT_TRUE(file.geometry.jd_M.isApprox(preset.geometry.jd_M));
  EXPECT_EQ(file.geometry.home_height_m, 1.511);
  EXPECT_EQ(file.drive.lead_m, 0.010);
  EXPECT_EQ(file.drive.pr_sign, 1);
  EXPECT_EQ(file.p_MoA_M, Vector3(1.2, 0, 0));
  EXPECT_NEAR(file.limits.joint_angle_max_rad, 75.0 * M_PI / 180.0, 1e-15);
}

TEST(Config, MinimalPresetFileGetsDefaults) {
  const PlatformConfig c = ParseConfig(kPreset, "rig.toml");
  EXPECT_EQ(c.drive.lead_m, 0.010);
  EXPECT_EQ(c.p_MoA_M, Vector3(1.2, 0, 0));
  EXPECT_EQ(c.geometry.home_height_m, 1.511);
}

TEST(Config, ExplicitArraysReproduceThePresetExactly) {
  const PlatformConfig c = ParseConfig(ExplicitGeometry(Huang2021Geometry()), "rig.toml");
  EXPECT_TRUE(c.preset.empty());
  const PlatformModel a(c), b(Huang2021Config());
  EXPECT_LT((a.home_length_m() - b.home_length_m()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((a.home_twist_rad() - b.home_twist_rad()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(Config, ExplicitArrayOverridesThePresetOneKeyAtATime) {
  PlatformGeometry moved = Huang2021Geometry();
  moved.p_BoBi_B(2, 0) = 0.004;  // base joint 1 sits 4 mm high
  const std::string text = std::string(kPreset) + "base_joints_m = " + Rows(moved.p_BoBi_B) + "\n";
  const PlatformConfig c = ParseConfig(text, "rig.toml");
  EXPECT_EQ(c.geometry.p_BoBi_B(2, 0), 0.004);
  EXPECT_TRUE(c.geometry.p_MoPi_M.isApprox(Huang2021Geometry().p_MoPi_M));
  const double stretch = PlatformModel(c).home_length_m()(0) - PlatformModel(Huang2021Config()).home_length_m()(0);
  EXPECT_LT(stretch, 0.0);  // a higher base joint shortens leg 1
}

TEST(Config, HomeHeightKeyMovesHome) {
  const PlatformConfig c = ParseConfig(std::string(kPreset) + "home_height_m = 1.6\n", "rig.toml");
  EXPECT_EQ(PlatformModel(c).home_pose().p_BoMo_B.z(), 1.6);
}

TEST(Config, MissingFileIsNamed) {
  try {
    LoadConfigFile("/nonexistent/edsp.toml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/edsp.toml"), std::string::npos);
  }
}

TEST(Config, SyntaxErrorGivesLineAndColumn) {
  EXPECT_CONFIG_ERROR("[geometry]\npreset = \"huang2021\n", "rig.toml:2:");
}

TEST(Config, StructuralErrorsNameTheKey) {
  EXPECT_CONFIG_ERROR("[drive]\nlead_m = 0.01\n", "missing section [geometry]");
  EXPECT_CONFIG_ERROR("geometry = 3\n", "[geometry] must be a table");
  EXPECT_CONFIG_ERROR("[geometry]\npreset = \"gough1962\"\n", "preset", "gough1962");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "[drive]\nlead = 0.01\n", "unknown key [drive] lead", "lead_m");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "[drive]\nlead_m = \"10mm\"\n", "[drive] lead_m must be a number");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "[drive]\npr_sign = 1.0\n", "[drive] pr_sign must be an integer");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "[geometry.sub]\n", "unknown key [geometry] sub");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "base_axes = [[1, 0, 0]]\n",
                      "[geometry] base_axes must be an array of 6 rows");
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "[observation]\npoint_m = [1.2, 0]\n",
                      "[observation] point_m must be [x, y, z]");
}

TEST(Config, WithoutPresetEveryArrayIsRequired) {
  const std::string full = ExplicitGeometry(Huang2021Geometry());
  for (const char* key : {"base_joints_m", "platform_joints_m", "base_axes", "platform_axes", "home_height_m"}) {
    std::string text = full;
    const std::size_t at = text.find(std::string(key) + " =");
    text.erase(at, text.find('\n', at) - at + 1);
    EXPECT_CONFIG_ERROR(text, "missing key [geometry]", key);
  }
  std::string no_point = full.substr(0, full.find("[observation]"));
  EXPECT_CONFIG_ERROR(no_point, "missing key [observation] point_m");
}

TEST(Config, AbsurdValuesAreRejectedWithTheValue) {
  const std::string p = kPreset;
  EXPECT_CONFIG_ERROR(p + "home_height_m = -1.5\n", "home_height_m", "-1.5");
  EXPECT_CONFIG_ERROR(p + "home_height_m = nan\n", "home_height_m", "finite");
  EXPECT_CONFIG_ERROR(p + "[drive]\nlead_m = 0\n", "[drive] lead_m = 0");
  EXPECT_CONFIG_ERROR(p + "[drive]\nlead_m = -0.01\n", "[drive] lead_m = -0.01");
  EXPECT_CONFIG_ERROR(p + "[drive]\nlead_m = 10\n", "[drive] lead_m = 10");  // mm typed as m
  EXPECT_CONFIG_ERROR(p + "[drive]\nlead_m = inf\n", "[drive] lead_m", "finite");
  EXPECT_CONFIG_ERROR(p + "[drive]\npr_sign = 2\n", "[drive] pr_sign = 2");
  EXPECT_CONFIG_ERROR(p + "[drive]\ngear_ratio = 0\n", "[drive] gear_ratio = 0");
  EXPECT_CONFIG_ERROR(p + "[limits]\nleg_min_m = 2.5\n", "[limits] leg_min_m = 2.5");
  EXPECT_CONFIG_ERROR(p + "[limits]\njoint_angle_max_rad = 2\n", "joint_angle_max_rad = 2");
  EXPECT_CONFIG_ERROR(p + "[limits]\njacobian_condition_max = 0.5\n", "jacobian_condition_max");
  EXPECT_CONFIG_ERROR(p + "[limits]\nleg_speed_max_m_s = 0\n", "[limits] leg_speed_max_m_s = 0");
  EXPECT_CONFIG_ERROR(p + "[limits]\nleg_speed_max_m_s = 500\n", "leg_speed_max_m_s = 500");  // mm/s as m/s
  EXPECT_CONFIG_ERROR(p + "[observation]\npoint_m = [1e9, 0, 0]\n", "[observation] point_m");
  EXPECT_CONFIG_ERROR(p + "[motion]\nspeed_max_m_s = 100\n", "[motion] speed_max_m_s = 100");  // mm/s as m/s
  EXPECT_CONFIG_ERROR(p + "[motion]\naccel_max_rad_s2 = -1\n", "[motion] accel_max_rad_s2 = -1");
  EXPECT_CONFIG_ERROR(p + "[motion]\njerk_max_m_s3 = nan\n", "[motion] jerk_max_m_s3");
  EXPECT_CONFIG_ERROR(p + "[motion]\non_target_tolerance_m = 0\n", "[motion] on_target_tolerance_m = 0");
  EXPECT_CONFIG_ERROR(p + "[motion]\non_target_settle_s = 100\n", "[motion] on_target_settle_s = 100");
  EXPECT_CONFIG_ERROR(p + "[motion]\nspeed_m_s = 0.1\n", "unknown key [motion] speed_m_s");
}

TEST(Config, MotionLimitsAreReadAndDefaulted) {
  const PlatformConfig c =
      ParseConfig(std::string(kPreset) + "[motion]\nspeed_max_m_s = 0.05\nleg_accel_max_m_s2 = 2\n", "t");
  EXPECT_EQ(c.motion.speed_max_m_s, 0.05);
  EXPECT_EQ(c.motion.leg_accel_max_m_s2, 2.0);
  EXPECT_EQ(c.motion.speed_max_rad_s, MotionLimits{}.speed_max_rad_s);
}

TEST(Config, NonUnitAxisIsNamedByRow) {
  Matrix36 axes = Huang2021Geometry().ja_B;
  axes.col(3) *= 2.0;
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "base_axes = " + Rows(axes) + "\n", "[geometry] base_axes row 4",
                      "unit vector");
}

TEST(Config, CoincidentJointsAreNamedByRow) {
  Matrix36 joints = Huang2021Geometry().p_MoPi_M;
  joints.col(4) = joints.col(1);
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "platform_joints_m = " + Rows(joints) + "\n",
                      "[geometry] platform_joints_m rows 2 and 5", "distinct");
}

TEST(Config, AxisAlongALegIsALockedJoint) {
  const PlatformModel model(Huang2021Config());
  Matrix36 axes = Huang2021Geometry().ja_B;
  const Vector3 leg = model.Solve(model.home_pose()).u_B.col(2);
  axes.col(2) = leg;
  EXPECT_CONFIG_ERROR(std::string(kPreset) + "base_axes = " + Rows(axes) + "\n", "base_axes row 3", "locked");
}

TEST(Config, DegenerateLayoutIsRejected) {
  // All six legs vertical: nothing resists sideways motion or yaw.
  PlatformGeometry g = Huang2021Geometry();
  g.p_BoBi_B = g.p_MoPi_M;
  g.ja_B = Matrix36::Zero();
  g.ja_B.row(0).setOnes();
  g.jd_M = g.ja_B;
  EXPECT_CONFIG_ERROR(ExplicitGeometry(g), "degenerate layout");
}

}  // namespace
}  // namespace edsp
