// The linearised model the diagnosis fits: its point-per-leg Jacobian against
// forward kinematics (an independent computation), the tracker frame
// estimate, and the leg-space bases against the rig's physics.
#include <random>

#include <gtest/gtest.h>

#include "edsp/diagnosis/design.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "random_pose_rows.h"
#include "platform_models.h"

namespace edsp::gap {
namespace {

// Rows at random poses, measured exactly in a tracker frame X_TB.
MeasurementData ExactData(const PlatformModel& model, const Pose& X_TB, int rows, PrMode compensation) {
  return RandomPoseRows(model, X_TB, rows, compensation, 0.15, 0.01, 7,
                        [](const Pose&, const Vector3& A) { return A; });
}

TEST(Design, PointPerLegMatchesForwardKinematicsOfPerturbedLegs) {
  const PlatformModel model = test_support::Huang2021Model();
  const Design d = BuildDesign(model, ExactData(model, Pose{}, 30, PrMode::kSigned));
  for (int k = 0; k < d.samples(); k += 7) {
    const Vector6 q = ExactData(model, Pose{}, 30, PrMode::kSigned)
                          .rows[static_cast<std::size_t>(d.source_row[static_cast<std::size_t>(k)])]
                          .pose_cmd;
    const Pose pose = Pose::FromVector(q);
    const Vector6 encoder = model.EncoderLengths(pose);
    for (int leg = 0; leg < 6; ++leg) {
      constexpr double kStep = 1e-5;
      Vector6 longer = encoder;
      longer(leg) += kStep;
      const FkResult fk = SolveForward(model, longer, pose);
      ASSERT_TRUE(fk.ok());
      const Vector3 moved = (model.ObservationPoint(fk.pose) - model.ObservationPoint(pose)) / kStep;
      EXPECT_LT((moved - d.point_per_leg[static_cast<std::size_t>(k)].col(leg)).norm(), 1e-4 * moved.norm() + 1e-6)
          << "sample " << k << " leg " << leg + 1;
    }
  }
}

// Legs on a quadratic in time (constant acceleration), sampled at stamps
// that jitter as a live tracker's do (±0.3 ms on a 10 ms spacing): the
// acceleration the servo-lag and compliance columns and the base-tilt
// check's load use is the motion's, not the jitter's (the evenly spaced
// second difference was off by ~1 m/s² here).
TEST(Design, AccelerationsOfUnevenlySpacedSamplesAreTheMotions) {
  const PlatformModel model = test_support::Huang2021Model();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-3e-4, 3e-4);
  MeasurementData d;
  d.runs = {"quadratic"};
  d.source = "synthetic";
  const Vector3 accel(0.4, -0.3, 1.2);  // m/s², the platform's, {B}
  const Vector3 start_velocity(0.1, 0.05, -0.2);
  for (int k = 0; k < 40; ++k) {
    MeasurementRow row;
    row.run = 0;
    row.time_s = 0.01 * k + jitter(rng);
    const double t = row.time_s;
    row.pose_cmd = model.home_pose().ToVector();
    row.pose_cmd.head<3>() += start_velocity * t + 0.5 * accel * t * t;
    const Pose pose = Pose::FromVector(row.pose_cmd);
    row.leg_cmd_m = model.CompensatedLengths(pose, PrMode::kSigned);
    row.point_m = model.ObservationPoint(pose);
    d.rows.push_back(row);
  }
  const Design design = BuildDesign(model, d);
  // The legs' own acceleration, by a second difference 1 ms wide at the
  // sample's instant (independent of the samples' spacing).
  auto legs_at = [&](double t) {
    Vector6 q = model.home_pose().ToVector();
    q.head<3>() += start_velocity * t + 0.5 * accel * t * t;
    return Vector6(model.CompensatedLengths(Pose::FromVector(q), PrMode::kSigned));
  };
  for (int k = 1; k + 1 < design.samples(); ++k) {
    const double t = design.time_s[static_cast<std::size_t>(k)];
    constexpr double kH = 1e-3;
    const Vector6 expected = (legs_at(t + kH) - 2.0 * legs_at(t) + legs_at(t - kH)) / (kH * kH);
    EXPECT_LT((design.leg_accel_m_s2[static_cast<std::size_t>(k)] - expected).norm(), 2e-3) << "sample " << k;
    // The payload's moment on the base: its weight less that acceleration
    // (per kg at {M}'s origin; a c.o.m. offset along x, the platform level).
    const Vector3 p =
        d.rows[static_cast<std::size_t>(design.source_row[static_cast<std::size_t>(k)])].pose_cmd.head<3>();
    const Vector3 force = Vector3(0.0, 0.0, -9.81) - accel;
    const Eigen::Matrix<double, 3, 4>& moment = design.load_moment_per_kg[static_cast<std::size_t>(k)];
    EXPECT_LT((moment.col(0) - p.cross(force)).norm(), 2e-3 * p.norm()) << "sample " << k;
    EXPECT_LT((moment.col(1) - Vector3::UnitX().cross(force)).norm(), 2e-3) << "sample " << k;
  }
}

TEST(Design, TrackerFrameIsEstimatedAndExactDataLeavesNoResidual) {
  const PlatformModel model = test_support::Huang2021Model();
  Pose X_TB;
  X_TB.p_BoMo_B = Vector3(2.0, -1.5, 0.3);
  X_TB.rpy_rad = Vector3(0.01, -0.02, 2.5);
  const Design d = BuildDesign(model, ExactData(model, X_TB, 60, PrMode::kSigned));
  EXPECT_LT((d.R0 - RotationFromRpy(X_TB.rpy_rad)).norm(), 1e-9);
  EXPECT_LT((d.t0 - X_TB.p_BoMo_B).norm(), 1e-9);
  EXPECT_LT(d.residual.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(d.applied_pr, PrMode::kSigned);
  EXPECT_EQ(d.run_samples.size(), 3u);
}

TEST(Design, AppliedCompensationIsRecognised) {
  const PlatformModel model = test_support::Huang2021Model();
  EXPECT_EQ(BuildDesign(model, ExactData(model, Pose{}, 30, PrMode::kNone)).applied_pr, PrMode::kNone);
  const Design unsigned_pr = BuildDesign(model, ExactData(model, Pose{}, 30, PrMode::kUnsigned));
  EXPECT_EQ(unsigned_pr.applied_pr, PrMode::kUnsigned);
}

TEST(Design, BacklashBasisFollowsThePlayOperatorHomedExtending) {
  const PlatformModel model = test_support::Huang2021Model();
  MeasurementData d;
  d.runs = {"legs"};
  d.source = "synthetic";
  // Leg 1 extends 1 mm, then retracts 10 µm (half the 20 µm play), then 1 mm.
  const double steps[] = {0.0, 1e-3, 1e-3 - 10e-6, 0.0};
  for (int k = 0; k < 4; ++k) {
    MeasurementRow row;
    row.time_s = k;
    row.pose_cmd = model.home_pose().ToVector();
    row.leg_cmd_m = model.home_length_m();
    row.leg_cmd_m(0) += steps[k];
    row.point_m = model.ObservationPoint(model.home_pose());
    d.rows.push_back(row);
  }
  DesignOptions o;
  o.backlash_width_m = 20e-6;
  const Design design = BuildDesign(model, d, o);
  const ColumnRange b = design.Of(Effect::kBacklash);
  // The basis is A's motion per metre of play taken up; its size against
  // the leg-1 offset column gives the share of the play (0, 0, ½, 1).
  const ColumnRange off = design.Of(Effect::kLegOffset);
  const double expected[] = {0.0, 0.0, 0.5, 1.0};
  for (int k = 0; k < 4; ++k) {
    const Vector3 play = design.columns.block<3, 1>(3 * k, b.begin);
    const Vector3 unit = design.columns.block<3, 1>(3 * k, off.begin);
    EXPECT_NEAR(play.dot(unit) / unit.squaredNorm(), expected[k], 1e-9) << "sample " << k;
  }
}

}  // namespace
}  // namespace edsp::gap
