// The huang2021 preset decodes architecture.md's table exactly and reproduces
// the paper's Eqs. (5)-(6).
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {
namespace {

TEST(Huang2021Geometry, Leg1JointsWhereArchitectureSaysTheyAre) {
  const PlatformGeometry g = Huang2021Geometry();
  EXPECT_NEAR(g.p_BoBi_B(0, 0), 0.876144, 5e-7);
  EXPECT_NEAR(g.p_BoBi_B(1, 0), 1.217527, 5e-7);
  EXPECT_EQ(g.p_BoBi_B(2, 0), 0.0);
  EXPECT_NEAR(g.p_MoPi_M(0, 0), 1.195826, 5e-7);
  EXPECT_NEAR(g.p_MoPi_M(1, 0), 0.1, 1e-12);
  EXPECT_EQ(g.p_MoPi_M(2, 0), 0.0);
}

TEST(Huang2021Geometry, JointPairsAreAChordApartOnTheirCircles) {
  const PlatformGeometry g = Huang2021Geometry();
  // Base pairs (legs 1&6, 2&3, 4&5) are db apart, platform pairs (1&2, 3&4, 5&6) da.
  EXPECT_NEAR((g.p_BoBi_B.col(0) - g.p_BoBi_B.col(5)).norm(), 0.3, 1e-12);
  EXPECT_NEAR((g.p_BoBi_B.col(1) - g.p_BoBi_B.col(2)).norm(), 0.3, 1e-12);
  EXPECT_NEAR((g.p_BoBi_B.col(3) - g.p_BoBi_B.col(4)).norm(), 0.3, 1e-12);
  EXPECT_NEAR((g.p_MoPi_M.col(0) - g.p_MoPi_M.col(1)).norm(), 0.2, 1e-12);
  EXPECT_NEAR((g.p_MoPi_M.col(2) - g.p_MoPi_M.col(3)).norm(), 0.2, 1e-12);
  EXPECT_NEAR((g.p_MoPi_M.col(4) - g.p_MoPi_M.col(5)).norm(), 0.2, 1e-12);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_NEAR(g.p_BoBi_B.col(i).norm(), 1.5, 1e-12);
    EXPECT_NEAR(g.p_MoPi_M.col(i).norm(), 1.2, 1e-12);
  }
}

TEST(Huang2021Geometry, AxesAreThePapersEquations5And6) {
  const PlatformGeometry g = Huang2021Geometry();
  const double h = std::sqrt(3.0) / 2.0;
  const Vector3 ja[6] = {{-h, 0.5, 0}, {h, 0.5, 0}, {h, 0.5, 0}, {0, -1, 0}, {0, -1, 0}, {-h, 0.5, 0}};
  const Vector3 jd0[6] = {{0, 1, 0}, {0, 1, 0}, {h, -0.5, 0}, {h, -0.5, 0}, {-h, -0.5, 0}, {-h, -0.5, 0}};
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_LT((g.ja_B.col(i) - ja[i]).norm(), 1e-15) << "leg " << i + 1;
    EXPECT_LT((g.jd_M.col(i) - jd0[i]).norm(), 1e-15) << "leg " << i + 1;
  }
}

TEST(Huang2021Geometry, EveryLegIs1p906353mLongAtHome) {
  const PlatformModel model(Huang2021Config());
  for (int i = 0; i < kNumLegs; ++i) EXPECT_NEAR(model.home_length_m()(i), 1.906353, 5e-7);
}

TEST(Huang2021Geometry, MirrorLegsSitAtOppositeTwistsOfAbout70p5DegAtHome) {
  const PlatformModel model(Huang2021Config());
  const Vector6& twist = model.home_twist_rad();
  for (int i = 0; i < kNumLegs; i += 2) {
    EXPECT_NEAR(twist(i), -twist(i + 1), 1e-12);
    EXPECT_NEAR(std::abs(twist(i)) * 180.0 / M_PI, 70.5, 0.1);
  }
}

}  // namespace
}  // namespace edsp
