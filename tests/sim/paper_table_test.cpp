// The paper-table evaluation: what each compensation mode achieves on the
// paper's four motions.
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/sim/paper_table.h"

namespace edsp {
namespace {

constexpr std::size_t kNoneColumn = 0, kUnsignedColumn = 1, kSignedColumn = 2, kAsinColumn = 3;

TEST(PaperTable, MotionsSpanThePapersRangesIn41Poses) {
  const PlatformModel model(Huang2021Config());
  const auto motions = PaperTestMotions();
  ASSERT_EQ(motions.size(), 4u);
  EXPECT_EQ(motions[0].name, "Lz");
  const auto poses = MotionPoses(motions[2], model.home_pose(), 41);  // Rz
  ASSERT_EQ(poses.size(), 41u);
  EXPECT_NEAR(poses.front().rpy_rad.z(), -M_PI / 6, 1e-15);
  EXPECT_NEAR(poses[20].rpy_rad.z(), 0.0, 1e-15);
  EXPECT_NEAR(poses.back().rpy_rad.z(), M_PI / 6, 1e-15);
  EXPECT_EQ(poses[7].p_BoMo_B, model.home_pose().p_BoMo_B);
}

TEST(PaperTable, SignedCompensationIsExactUnsignedIsWorseThanNone) {
  const PlatformModel model(Huang2021Config());
  for (const MotionRow& row : PaperTable(model)) {
    SCOPED_TRACE(row.motion.name);
    EXPECT_LT(row.max_error_m[kSignedColumn], 1e-9);
    EXPECT_GT(row.max_error_m[kNoneColumn], 1e-4);  // PR at a 10 mm lead is ~0.1 mm or more
    EXPECT_GT(row.max_error_m[kUnsignedColumn], row.max_error_m[kNoneColumn]);
  }
}

TEST(PaperTable, ErrorScalesWithTheLead) {
  PlatformConfig config = Huang2021Config();
  const auto base = PaperTable(PlatformModel(config), 11);
  config.drive.lead_m = 0.005;
  const auto half = PaperTable(PlatformModel(config), 11);
  for (std::size_t m = 0; m < base.size(); ++m) {
    EXPECT_NEAR(half[m].max_error_m[kNoneColumn], 0.5 * base[m].max_error_m[kNoneColumn],
                0.01 * base[m].max_error_m[kNoneColumn]);
  }
}

TEST(PaperTable, LinuxCncAsinHoldsUpToAbout13DegOfYawThenBreaks) {
  const PlatformModel model(Huang2021Config());
  auto miss = [&](double yaw_deg, PrMode mode) {
    Pose pose = model.home_pose();
    pose.rpy_rad.z() = yaw_deg * M_PI / 180.0;
    return PointAError(model, pose, mode);
  };
  EXPECT_LT(miss(12.0, PrMode::kAsin), 1e-9);
  EXPECT_LT(miss(-12.0, PrMode::kAsin), 1e-9);
  EXPECT_GT(miss(14.0, PrMode::kAsin), 1e-5);
  EXPECT_GT(miss(30.0, PrMode::kAsin), miss(30.0, PrMode::kNone));
  const auto rows = PaperTable(model);
  EXPECT_LT(rows[0].max_error_m[kAsinColumn], 1e-9);  // Lz, Lx, Ry never fold
  EXPECT_LT(rows[1].max_error_m[kAsinColumn], 1e-9);
  EXPECT_LT(rows[3].max_error_m[kAsinColumn], 1e-9);
}

TEST(PaperTable, PoseOutsideTheWorkspaceIsNamed) {
  PlatformConfig config = Huang2021Config();
  config.limits.leg_max_m = 2.2;
  try {
    PaperTable(PlatformModel(config));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("motion Lz"), std::string::npos) << message;
    EXPECT_NE(message.find("leg_max_m"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace edsp
