// Analytic Jacobians against central finite differences.
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "random_poses.h"

namespace edsp {
namespace {

constexpr double kStep = 1e-6;

template <typename F>
Matrix6 CentralDifference(const Pose& pose, F f) {
  Matrix6 J;
  for (int k = 0; k < 6; ++k) {
    Vector6 plus = pose.ToVector(), minus = pose.ToVector();
    plus(k) += kStep;
    minus(k) -= kStep;
    J.col(k) = (f(Pose::FromVector(plus)) - f(Pose::FromVector(minus))) / (2.0 * kStep);
  }
  return J;
}

TEST(Jacobian, LengthJacobianMatchesFiniteDifferences) {
  const PlatformModel model(Huang2021Config());
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 300, 21)) {
    const Matrix6 fd = CentralDifference(pose, [&](const Pose& p) { return model.LegLengths(p); });
    EXPECT_LT((model.LengthJacobian(pose) - fd).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(Jacobian, PrErrorJacobianMatchesFiniteDifferences) {
  PlatformConfig config = Huang2021Config();
  config.drive.pr_sign = -1;  // the sign must flow through
  const PlatformModel model(config);
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 300, 22)) {
    const Matrix6 fd = CentralDifference(pose, [&](const Pose& p) { return model.PrLengthError(p, PrMode::kSigned); });
    const Matrix6 analytic = model.PrLengthErrorJacobian(pose);
    EXPECT_LT((analytic - fd).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_GT(analytic.cwiseAbs().maxCoeff(), 1e-4);  // not trivially zero
  }
}

TEST(Jacobian, TwistJacobianMatchesSmallSpatialMotions) {
  // Move the platform by a spatial twist [v; ω] directly on R and p (no rpy):
  // length rates must be J·[v; ω].
  const PlatformModel model(Huang2021Config());
  const PlatformGeometry& g = model.config().geometry;
  auto lengths = [&](const Matrix3& R, const Vector3& p) {
    return Vector6(((R * g.p_MoPi_M - g.p_BoBi_B).colwise() + p).colwise().norm().transpose());
  };
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 300, 23)) {
    const Matrix3 R = RotationFromRpy(pose.rpy_rad);
    Matrix6 fd;
    for (int k = 0; k < 6; ++k) {
      Vector6 twist = Vector6::Zero();
      twist(k) = kStep;
      const Vector3 w = twist.tail<3>();
      const Matrix3 dR = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).matrix() : Matrix3::Identity();
      const Vector6 plus = lengths(dR * R, pose.p_BoMo_B + twist.head<3>());
      const Vector6 minus = lengths(dR.transpose() * R, pose.p_BoMo_B - twist.head<3>());
      fd.col(k) = (plus - minus) / (2.0 * kStep);
    }
    EXPECT_LT((model.TwistJacobian(pose) - fd).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(Jacobian, RotationDerivativesMatchFiniteDifferences) {
  const Vector3 rpy(0.3, -0.4, 1.1);
  const auto dR = RotationRpyDerivatives(rpy);
  for (int k = 0; k < 3; ++k) {
    Vector3 plus = rpy, minus = rpy;
    plus(k) += kStep;
    minus(k) -= kStep;
    const Matrix3 fd = (RotationFromRpy(plus) - RotationFromRpy(minus)) / (2.0 * kStep);
    EXPECT_LT((dR[static_cast<std::size_t>(k)] - fd).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(Rotation, IsEquation3AsElementaryRotations) {
  const Vector3 rpy(0.3, -0.4, 1.1);
  const Matrix3 expected = (Eigen::AngleAxisd(rpy.z(), Vector3::UnitZ()) *
                            Eigen::AngleAxisd(rpy.y(), Vector3::UnitY()) * Eigen::AngleAxisd(rpy.x(), Vector3::UnitX()))
                               .matrix();
  EXPECT_LT((RotationFromRpy(rpy) - expected).cwiseAbs().maxCoeff(), 1e-15);
}

}  // namespace
}  // namespace edsp
