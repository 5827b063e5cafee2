// The Ceres fit against data made by forward kinematics with known leg
// offsets and a known tracker frame (independent of the linearised model):
// it recovers them, its σ covers the truth, and tracker spikes on 2% of the
// samples do not pull it, where plain least squares is pulled.
#include <random>

#include <gtest/gtest.h>

#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/robust_fit.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"

namespace edsp::gap {
namespace {

const Vector6 kOffset = (Vector6() << 80e-6, -60e-6, 40e-6, -100e-6, 50e-6, -20e-6).finished();
constexpr double kRobustFitNoise = 5e-6;

MeasurementData OffsetData(const PlatformModel& model, double spike_share) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0), share(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, kRobustFitNoise);
  const Matrix3 R = RotationFromRpy(Vector3(0.01, 0.02, 1.0));
  const Vector3 t(1.0, -2.0, 0.5);
  MeasurementData d;
  d.runs = {"a", "b", "c", "d"};
  d.source = "synthetic";
  for (int k = 0; k < 800; ++k) {
    MeasurementRow row;
    row.run = k / 200;
    row.time_s = 0.01 * k;
    row.pose_cmd = model.home_pose().ToVector();
    row.pose_cmd.head<3>() += 0.2 * Vector3(u(rng), u(rng), u(rng));
    row.pose_cmd.tail<3>() += 0.2 * Vector3(u(rng), u(rng), u(rng));
    const Pose target = Pose::FromVector(row.pose_cmd);
    row.leg_cmd_m = model.CompensatedLengths(target, PrMode::kSigned);
    // The drives realise the command; the legs are longer by the offsets.
    const FkResult fk = SolveForward(model, row.leg_cmd_m + kOffset, target);
    EXPECT_TRUE(fk.ok());
    row.point_m = R * model.ObservationPoint(fk.pose) + t + Vector3(noise(rng), noise(rng), noise(rng));
    if (share(rng) < spike_share) row.point_m.z() += 2e-3;  // the beam clipped a cable
    d.rows.push_back(row);
  }
  return d;
}

Columns OffsetColumns(const Design& d) {
  Columns c;
  for (int k = 0; k < 6; ++k) c.push_back(d.Of(Effect::kLegOffset).begin + k);
  return c;
}

TEST(RobustFit, RecoversLegOffsetsWithUncertaintiesThatCoverThem) {
  const PlatformModel model(Huang2021Config());
  const Design d = BuildDesign(model, OffsetData(model, 0.0));
  const RobustFit fit = FitRobust(d, OffsetColumns(d), Vector6::Zero(), 3.0 * std::sqrt(3.0) * kRobustFitNoise);
  ASSERT_TRUE(fit.converged);
  ASSERT_TRUE(fit.covariance_ok);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(fit.theta(i), kOffset(i), 4.0 * fit.sigma(i) + 0.2e-6) << "leg " << i + 1;
    EXPECT_GT(fit.sigma(i), 0.0);
    EXPECT_LT(fit.sigma(i), 20e-6);  // offsets resemble a frame shift: loosely determined
  }
  EXPECT_NEAR(std::sqrt(fit.residual.squaredNorm() / d.samples()), std::sqrt(3.0) * kRobustFitNoise, 1e-6);
}

TEST(RobustFit, TrackerSpikesDoNotPullTheHuberFitWhereLeastSquaresIsPulled) {
  const PlatformModel model(Huang2021Config());
  const Design d = BuildDesign(model, OffsetData(model, 0.02));
  const RobustFit fit = FitRobust(d, OffsetColumns(d), Vector6::Zero(), 3.0 * std::sqrt(3.0) * kRobustFitNoise);
  const GramSet gram(d, MakeFolds(d));
  Columns all_cols = ColumnsOf(d, {Effect::kLegOffset});
  const Eigen::VectorXd plain = gram.Solve(all_cols, gram.AllFolds(), Eigen::VectorXd::Zero(d.parameters()));
  const double robust_error = (fit.theta - kOffset).cwiseAbs().maxCoeff();
  const double plain_error = (plain.tail(6) - kOffset).cwiseAbs().maxCoeff();
  EXPECT_LT(robust_error, 4.0 * fit.sigma.maxCoeff());
  EXPECT_GT(plain_error, 3.0 * robust_error) << plain_error << " vs " << robust_error;
}

}  // namespace
}  // namespace edsp::gap
