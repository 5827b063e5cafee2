// The signed twist, checked against an independent computation: the relative
// rotation of the two leg bodies obtained by composing each Hooke's joint's
// two rotations (no cross products with the leg axis involved).
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "random_poses.h"

namespace edsp {
namespace {

// Orientation (columns: outer axis, inner axis, body axis, all carried by the
// body) of a body hung from a Hooke's joint whose outer axis is fixed in the
// parent frame, with the body axis pointing along `dir` (parent frame).
// Joint angles: alpha about the outer axis, then beta about the inner axis.
Matrix3 HookeBodyFrame(const Vector3& outer, const Vector3& dir) {
  const Vector3 c0 = (Vector3::UnitZ() - Vector3::UnitZ().dot(outer) * outer).normalized();
  const Vector3 k0 = c0.cross(outer);  // inner axis at zero joint angles
  const double beta = std::asin(dir.dot(outer));
  const double alpha = std::atan2(-dir.dot(k0), dir.dot(c0));
  const Matrix3 R = (Eigen::AngleAxisd(alpha, outer) * Eigen::AngleAxisd(beta, k0)).matrix();
  Matrix3 reference;
  reference << outer, k0, c0;
  return R * reference;
}

// Rotation of the upper leg body relative to the lower one about the leg axis.
Vector6 TwistByJointComposition(const PlatformModel& model, const Pose& pose) {
  const PlatformGeometry& g = model.config().geometry;
  const LegSolution legs = model.Solve(pose);
  Vector6 angle;
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = legs.u_B.col(i);
    const Matrix3 lower = HookeBodyFrame(g.ja_B.col(i), u);
    const Matrix3 upper = legs.R_BM * HookeBodyFrame(g.jd_M.col(i), legs.R_BM.transpose() * u);
    EXPECT_LT((lower.col(2) - u).norm(), 1e-12);  // both bodies lie along the leg
    EXPECT_LT((upper.col(2) - u).norm(), 1e-12);
    const Matrix3 relative = lower.transpose() * upper;  // a rotation about the body axis
    angle(i) = std::atan2(relative(1, 0), relative(0, 0));
  }
  return angle;
}

TEST(SignedTwist, ChangeFromHomeMatchesHookeJointCompositionOver5000Poses) {
  const PlatformModel model(Huang2021Config());
  const Vector6 home = TwistByJointComposition(model, model.home_pose());
  double worst = 0.0;
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 5000, 11)) {
    const Vector6 composed = TwistByJointComposition(model, pose) - home;
    const Vector6 formula = model.Solve(pose).twist_rad - model.home_twist_rad();
    for (int i = 0; i < kNumLegs; ++i) {
      worst = std::max(worst, std::abs(WrapAngle(composed(i) - formula(i))));
    }
  }
  EXPECT_LT(worst, 1e-10);
}

TEST(SignedTwist, UnsignedModeIsThePapersArccos) {
  const PlatformModel model(Huang2021Config());
  const PlatformGeometry& g = model.config().geometry;
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 500, 12)) {
    const LegSolution legs = model.Solve(pose);
    for (int i = 0; i < kNumLegs; ++i) {
      const Vector3 u = legs.u_B.col(i);
      const Vector3 jb = u.cross(g.ja_B.col(i)).normalized();  // Eq. (8)
      const Vector3 je = u.cross(legs.jd_B.col(i)).normalized();
      EXPECT_NEAR(TwistAsModelled(legs.twist_rad(i), PrMode::kUnsigned), std::acos(jb.dot(je)),
                  1e-7);  // arccos itself is only this good near its ends
    }
  }
}

TEST(SignedTwist, AsinModeIsGenhexkinsDotProduct) {
  // LinuxCNC: nb3 = u×(ja×u), na2 = (R·jd0)×u, correction ∝ asin(nb3·na2).
  const PlatformModel model(Huang2021Config());
  const PlatformGeometry& g = model.config().geometry;
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 500, 13)) {
    const LegSolution legs = model.Solve(pose);
    for (int i = 0; i < kNumLegs; ++i) {
      const Vector3 u = legs.u_B.col(i);
      const Vector3 nb3 = u.cross(Vector3(g.ja_B.col(i)).cross(u)).normalized();
      const Vector3 na2 = Vector3(legs.jd_B.col(i)).cross(u).normalized();
      EXPECT_NEAR(TwistAsModelled(legs.twist_rad(i), PrMode::kAsin), std::asin(nb3.dot(na2)), 1e-7);
    }
  }
}

TEST(SignedTwist, PureYawTwistsAllSixLegsTheSameWayWhileUnsignedAlternates) {
  const PlatformModel model(Huang2021Config());
  for (double yaw_deg : {-30.0, -10.0, -1.0, 1.0, 10.0, 30.0}) {
    Pose pose = model.home_pose();
    pose.rpy_rad.z() = yaw_deg * M_PI / 180.0;
    const Vector6 signed_error = model.PrLengthError(pose, PrMode::kSigned);
    const Vector6 unsigned_error = model.PrLengthError(pose, PrMode::kUnsigned);
    const double sign = signed_error(0) > 0.0 ? 1.0 : -1.0;
    for (int i = 0; i < kNumLegs; ++i) {
      EXPECT_GT(sign * signed_error(i), 0.0) << "leg " << i + 1 << " at yaw " << yaw_deg;
      // The paper's arccos reports the mirror-image legs' twist backwards: the
      // sign alternates from one leg to the next, magnitudes stay the same.
      EXPECT_LT(unsigned_error(i) * unsigned_error((i + 1) % kNumLegs), 0.0)
          << "legs " << i + 1 << "," << (i + 1) % kNumLegs + 1 << " at yaw " << yaw_deg;
      EXPECT_NEAR(std::abs(unsigned_error(i)), std::abs(signed_error(i)), 1e-15);
    }
  }
  // And the common sign follows the direction of the yaw.
  Pose left = model.home_pose(), right = model.home_pose();
  left.rpy_rad.z() = -0.1;
  right.rpy_rad.z() = 0.1;
  EXPECT_LT(model.PrLengthError(left, PrMode::kSigned)(0) * model.PrLengthError(right, PrMode::kSigned)(0), 0.0);
}

TEST(SignedTwist, PrErrorIsSignTimesTwistChangeOverTwoPiTimesLead) {
  PlatformConfig config = Huang2021Config();
  config.drive.lead_m = 0.005;
  config.drive.pr_sign = -1;
  const PlatformModel model(config);
  Pose pose = model.home_pose();
  pose.rpy_rad << 0.1, -0.2, 0.3;
  const LegSolution legs = model.Solve(pose);
  const Vector6 expected = -1.0 * (legs.twist_rad - model.home_twist_rad()) / (2.0 * M_PI) * 0.005;
  EXPECT_LT((model.PrLengthError(legs, PrMode::kSigned) - expected).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_EQ(model.PrLengthError(legs, PrMode::kNone), Vector6::Zero());
}

TEST(SignedTwist, IsZeroChangeAtHomeForEveryMode) {
  const PlatformModel model(Huang2021Config());
  for (PrMode mode : {PrMode::kNone, PrMode::kUnsigned, PrMode::kSigned, PrMode::kAsin}) {
    EXPECT_EQ(model.PrLengthError(model.home_pose(), mode), Vector6::Zero()) << PrModeName(mode);
  }
}

TEST(PrMode, ParsesNamesAndWireValues) {
  PrMode mode = PrMode::kNone;
  EXPECT_TRUE(ParsePrMode("signed", &mode));
  EXPECT_EQ(mode, PrMode::kSigned);
  EXPECT_TRUE(ParsePrMode("1", &mode));
  EXPECT_EQ(mode, PrMode::kUnsigned);
  EXPECT_FALSE(ParsePrMode("7", &mode));
  EXPECT_FALSE(ParsePrMode("Signed", &mode));
}

TEST(WrapAngle, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(3.0 * M_PI), M_PI);
  EXPECT_DOUBLE_EQ(WrapAngle(-M_PI), M_PI);
  EXPECT_NEAR(WrapAngle(2.0 * M_PI + 0.25), 0.25, 1e-15);
  EXPECT_NEAR(WrapAngle(-0.25), -0.25, 1e-15);
}

}  // namespace
}  // namespace edsp
