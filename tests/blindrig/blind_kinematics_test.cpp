// The blind rig's kinematics and edsp's are written apart (joint angles and
// AngleAxis against cross products and Eq. 3): on random poses across the
// workspace they must agree, which checks both.
#include <random>

#include <gtest/gtest.h>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::blind {
namespace {

std::vector<Vec6> RandomPoses(const Vec6& home, int count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec6> poses;
  for (int k = 0; k < count; ++k) {
    Vec6 q = home;
    for (int a = 0; a < 3; ++a) q(a) += 0.3 * unit(rng);
    for (int a = 3; a < 6; ++a) q(a) += 0.4 * unit(rng);  // ±23°
    poses.push_back(q);
  }
  return poses;
}

TEST(BlindKinematics, RotationAndLegLengthsAgreeWithEdspsInverseKinematics) {
  const PlatformConfig config = Huang2021Config();
  const PlatformModel model(config);
  const BlindRigSetup setup = SetupFromConfig(config);
  for (const Vec6& q : RandomPoses(HomePose(setup.geometry), 200)) {
    const Pose pose = Pose::FromVector(q);
    EXPECT_LT((Rotation(q) - RotationFromRpy(pose.rpy_rad)).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((LegLengths(setup.geometry, q) - model.LegLengths(pose)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(BlindKinematics, TwistFromJointAnglesAgreesWithEdspsSignedPassiveRotation) {
  const PlatformConfig config = Huang2021Config();
  const PlatformModel model(config);
  const BlindRigSetup setup = SetupFromConfig(config);
  const Vec6 home = HomePose(setup.geometry);
  const Vec6 home_twist = LegBodyTwist(setup.geometry, home);
  double largest = 0.0;
  for (const Vec6& q : RandomPoses(home, 200)) {
    const Vec6 edsp = model.PrLengthError(Pose::FromVector(q), PrMode::kSigned);
    const Vec6 twist = LegBodyTwist(setup.geometry, q);
    for (int i = 0; i < 6; ++i) {
      const double blind = setup.pr_sign * std::remainder(twist(i) - home_twist(i), 2 * kPi) / (2 * kPi) * setup.lead_m;
      EXPECT_NEAR(blind, edsp(i), 1e-12) << "leg " << i + 1;
      largest = std::max(largest, std::abs(edsp(i)));
    }
  }
  EXPECT_GT(largest, 1e-4) << "the poses must twist the legs measurably";
}

TEST(BlindKinematics, NewtonOnFiniteDifferencesInvertsTheLegLengths) {
  const BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  const Vec6 home = HomePose(setup.geometry);
  for (const Vec6& q : RandomPoses(home, 20)) {
    const Vec6 lengths = LegLengths(setup.geometry, q);
    const Vec6 solved = SolvePose([&](const Vec6& x) { return Vec6(LegLengths(setup.geometry, x) - lengths); }, home);
    EXPECT_LT((solved - q).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// Along a sampled path one solver keeps its Jacobian, which costs twelve
// residuals to build: a path of small steps then costs a few residuals a
// pose, however far each path starts from where the last ended (a kept
// Jacobian that no longer shrinks the residual a hundredfold a step is built
// again). Each pose is the one a fresh Newton solve finds.
TEST(BlindKinematics, AKeptJacobianFindsThePosesAFreshSolveFinds) {
  const BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  const Vec6 home = HomePose(setup.geometry);
  const std::vector<Vec6> ends = RandomPoses(home, 6);
  PoseSolver solver;
  Vec6 carried = home;
  for (std::size_t p = 0; p + 1 < ends.size(); ++p) {
    constexpr int kSamples = 2000;  // 0.3 mm and 0.4 mrad apart at most: 0.3 m/s sampled at 1 kHz
    int evaluations = 0;
    for (int k = 0; k <= kSamples; ++k) {
      const Vec6 q = ends[p] + (ends[p + 1] - ends[p]) * (static_cast<double>(k) / kSamples);
      const Vec6 lengths = LegLengths(setup.geometry, q);
      const auto residual = [&](const Vec6& x) { return Vec6(LegLengths(setup.geometry, x) - lengths); };
      const auto counted = [&](const Vec6& x) {
        ++evaluations;
        return residual(x);
      };
      carried = solver.Solve(counted, carried);
      EXPECT_LT((carried - q).cwiseAbs().maxCoeff(), 1e-10) << "path " << p << ", sample " << k;
      if (k % 500 == 0) {
        EXPECT_LT((carried - SolvePose(residual, home)).cwiseAbs().maxCoeff(), 1e-11);
      }
    }
    EXPECT_LT(evaluations, 8 * (kSamples + 1)) << "path " << p;  // a fresh solve: 27 or more
  }
}

}  // namespace
}  // namespace edsp::blind
