// Compensation (Eqs. 11-12): commands built with the signed model put point A
// where it should be; other models miss by what a linearised model predicts.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "random_poses.h"

namespace edsp {
namespace {

Pose Reached(const PlatformModel& model, const Pose& target, PrMode mode) {
  // From home: the target itself would already be a root for the signed mode.
  const FkResult fk = SolveForward(model, model.CompensatedLengths(target, mode), model.home_pose());
  EXPECT_TRUE(fk.ok()) << FkStatusName(fk.status);
  return fk.pose;
}

TEST(Compensation, SignedLandsPointAWithin1nm) {
  const PlatformModel model(Huang2021Config());
  double worst = 0.0;
  for (const Pose& target : test_support::RandomWorkspacePoses(model, 2000, 41)) {
    const Pose reached = Reached(model, target, PrMode::kSigned);
    worst = std::max(worst, (model.ObservationPoint(reached) - model.ObservationPoint(target)).norm());
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(Compensation, CommandIsIkLengthMinusPrError) {
  const PlatformModel model(Huang2021Config());
  for (const Pose& pose : test_support::RandomWorkspacePoses(model, 100, 42)) {
    for (PrMode mode : {PrMode::kNone, PrMode::kUnsigned, PrMode::kSigned, PrMode::kAsin}) {
      const Vector6 expected = model.LegLengths(pose) - model.PrLengthError(pose, mode);
      EXPECT_LT((model.CompensatedLengths(pose, mode) - expected).cwiseAbs().maxCoeff(), 1e-15);
    }
  }
}

TEST(Compensation, UncompensatedMissMatchesLinearisedPrediction) {
  // Commanding plain IK lengths, the legs grow by the PR error e, so the pose
  // moves by about J⁻¹·e: an estimate that uses no Newton iteration at all.
  const PlatformModel model(Huang2021Config());
  for (const Pose& target : test_support::RandomWorkspacePoses(model, 200, 43)) {
    const Vector6 e = model.PrLengthError(target, PrMode::kSigned);
    if (e.norm() < 1e-5) continue;
    const Vector6 predicted = model.LengthJacobian(target).partialPivLu().solve(e);
    const Vector6 actual = Reached(model, target, PrMode::kNone).ToVector() - target.ToVector();
    EXPECT_LT((actual - predicted).norm(), 0.02 * predicted.norm());
  }
}

TEST(Compensation, UnsignedModelIsWorseThanNoneUnderYaw) {
  const PlatformModel model(Huang2021Config());
  Pose target = model.home_pose();
  target.rpy_rad.z() = 0.4;
  auto miss = [&](PrMode mode) {
    return (model.ObservationPoint(Reached(model, target, mode)) - model.ObservationPoint(target)).norm();
  };
  EXPECT_GT(miss(PrMode::kUnsigned), 1.5 * miss(PrMode::kNone));
  EXPECT_GT(miss(PrMode::kNone), 1e-4);
}

}  // namespace
}  // namespace edsp
