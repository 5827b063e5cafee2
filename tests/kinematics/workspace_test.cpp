// Each workspace limit bites where it should and says which limit it was.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <limits>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/path_check.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {
namespace {

Pose Moved(const PlatformModel& model, const Vector6& delta) {
  return Pose::FromVector(model.home_pose().ToVector() + delta);
}

TEST(Workspace, HomeAndThePapersExtremesAreInside) {
  const PlatformModel model(Huang2021Config());
  EXPECT_TRUE(CheckWorkspace(model, model.home_pose()).ok());
  for (int axis = 0; axis < 6; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      Vector6 delta = Vector6::Zero();
      delta(axis) = sign * (axis < 3 ? 0.5 : 30.0 * M_PI / 180.0);
      const WorkspaceCheck check = CheckWorkspace(model, Moved(model, delta));
      EXPECT_TRUE(check.ok()) << "axis " << axis << ": " << check.Describe();
    }
  }
}

TEST(Workspace, NonFinitePoseIsRefused) {
  const PlatformModel model(Huang2021Config());
  Pose pose = model.home_pose();
  pose.rpy_rad.x() = std::nan("");
  EXPECT_EQ(CheckWorkspace(model, pose).limit, WorkspaceLimit::kNonFinite);
}

TEST(Workspace, LegStrokeLimitsNameLegAndKey) {
  const PlatformModel model(Huang2021Config());
  Vector6 up = Vector6::Zero(), down = Vector6::Zero();
  up(2) = 0.7;
  down(2) = -0.75;
  const WorkspaceCheck too_long = CheckWorkspace(model, Moved(model, up));
  EXPECT_EQ(too_long.limit, WorkspaceLimit::kLegTooLong);
  EXPECT_NE(too_long.Describe().find("leg_max_m"), std::string::npos) << too_long.Describe();
  EXPECT_NE(too_long.Describe().find("leg 1"), std::string::npos) << too_long.Describe();
  EXPECT_EQ(CheckWorkspace(model, Moved(model, down)).limit, WorkspaceLimit::kLegTooShort);
}

TEST(Workspace, JointAngleLimitsAtBothPlatforms) {
  PlatformConfig config = Huang2021Config();
  config.limits.joint_angle_max_rad = 40.0 * M_PI / 180.0;
  config.limits.leg_max_m = 3.0;
  const PlatformModel model(config);
  Vector6 sideways = Vector6::Zero();
  sideways(0) = 0.3;
  const WorkspaceCheck base = CheckWorkspace(model, Moved(model, sideways));
  EXPECT_EQ(base.limit, WorkspaceLimit::kBaseJointAngle) << base.Describe();
  EXPECT_NE(base.Describe().find("joint_angle_max_rad"), std::string::npos);
  // Tilted and shifted against the tilt: leg 3 leans away from the platform
  // normal while every leg stays within the limit at the base.
  config.limits.joint_angle_max_rad = 45.0 * M_PI / 180.0;
  const PlatformModel tight(config);
  Vector6 tilt = Vector6::Zero();
  tilt(0) = -0.2;
  tilt(4) = 0.2;
  const WorkspaceCheck platform = CheckWorkspace(tight, Moved(tight, tilt));
  EXPECT_EQ(platform.limit, WorkspaceLimit::kPlatformJointAngle) << platform.Describe();
  EXPECT_EQ(platform.leg, 2);
  EXPECT_NE(platform.Describe().find("platform normal"), std::string::npos);
}

TEST(Workspace, ConditioningLimit) {
  PlatformConfig config = Huang2021Config();
  const PlatformModel model(config);
  const double condition = JacobianCondition(model, model.home_pose());
  EXPECT_GT(condition, 1.0);
  config.limits.jacobian_condition_max = 0.99 * condition;
  const WorkspaceCheck check = CheckWorkspace(PlatformModel(config), model.home_pose());
  EXPECT_EQ(check.limit, WorkspaceLimit::kConditioning);
  EXPECT_NEAR(check.value, condition, 1e-9 * condition);
  EXPECT_NE(check.Describe().find("jacobian_condition_max"), std::string::npos);
}

TEST(Workspace, TheConditionIsTheRatioOfTheExtremeSingularValues) {
  // Against an SVD of the same normalised Jacobian (the check solves JᵀJ's eigenvalues).
  const PlatformModel model(Huang2021Config());
  for (const Vector6& q : {Vector6(Vector6::Zero()), (Vector6() << 0.3, -0.2, 0.0, 0.2, -0.3, 0.4).finished()}) {
    Pose pose = Pose::FromVector(q);
    pose.p_BoMo_B.z() += model.home_pose().p_BoMo_B.z();
    Matrix6 J = model.TwistJacobian(pose);
    J.rightCols<3>() /= model.config().geometry.p_MoPi_M.colwise().norm().mean();
    const Eigen::JacobiSVD<Matrix6> svd(J);
    EXPECT_NEAR(JacobianCondition(model, pose), svd.singularValues()(0) / svd.singularValues()(5), 1e-9);
  }
}

TEST(Workspace, CheckLegsIsTheWorkspaceCheckWithoutTheConditioning) {
  const PlatformModel model(Huang2021Config());
  Pose far = model.home_pose();
  far.p_BoMo_B.z() = 3.0;
  EXPECT_EQ(CheckLegs(model, model.Solve(far)).limit, CheckWorkspace(model, far).limit);
  EXPECT_TRUE(CheckLegs(model, model.Solve(model.home_pose())).ok());
}

TEST(Workspace, ConditionGrowsTowardsTheRotationalSingularity) {
  // Yawing a 6-6 platform toward ~90° lines the legs up with the platform's
  // rotation: it loses stiffness about z and the condition number climbs.
  PlatformConfig config = Huang2021Config();
  config.limits.leg_max_m = 3.5;
  const PlatformModel model(config);
  double previous = JacobianCondition(model, model.home_pose());
  for (double yaw : {0.3, 0.6, 0.9, 1.2, 1.4}) {
    Vector6 delta = Vector6::Zero();
    delta(5) = yaw;
    const double condition = JacobianCondition(model, Moved(model, delta));
    EXPECT_GT(condition, previous) << "yaw " << yaw;
    previous = condition;
  }
  EXPECT_GT(previous, 5.0 * JacobianCondition(model, model.home_pose()));
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

TEST(PathCheck, APathOfNoFiniteDurationIsRefusedNotSampled) {
  const PlatformModel model(Huang2021Config());
  const Vector6 home = model.home_pose().ToVector();
  for (double duration :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1.0, 1e9}) {
    const PathCheck c = CheckPath(
        model, PathLimitsOf(model), [&](double) { return home; }, duration);
    EXPECT_EQ(c.limit, PathLimit::kDuration) << duration;
    EXPECT_NE(c.Describe().find("would last"), std::string::npos) << c.Describe();
  }
  EXPECT_TRUE(CheckPath(
                  model, PathLimitsOf(model), [&](double) { return home; }, 0.5)
                  .ok());
}

TEST(PathCheck, ALegOutrunningTheDrivesIsNamedWithItsTime) {
  const PlatformModel model(Huang2021Config());
  const Vector6 home = model.home_pose().ToVector();
  // z rises 1 m/s after t = 0.2 s: every leg faster than 0.5 m/s.
  const PathCheck c = CheckPath(
      model, PathLimitsOf(model),
      [&](double t) {
        Vector6 q = home;
        q(2) += std::max(0.0, t - 0.2);
        return q;
      },
      0.4);
  ASSERT_EQ(c.limit, PathLimit::kLegSpeed);
  EXPECT_NEAR(c.t_s, 0.201, 1e-9);
  EXPECT_NE(c.Describe().find("leg_speed_max_m_s = 0.5"), std::string::npos) << c.Describe();
}

}  // namespace
}  // namespace edsp
