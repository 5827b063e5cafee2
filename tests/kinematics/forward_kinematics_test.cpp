// Forward kinematics: round trips over 50 000 random workspace poses from
// perturbed guesses, and loud failure where there is no trustworthy answer.
#include <random>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "random_poses.h"
#include "sanitized_build.h"

namespace edsp {
namespace {

struct RoundTripStats {
  int converged = 0;
  int failed_loudly = 0;
  int silently_wrong = 0;  // claimed converged, but not to the true pose
  double worst_error = 0.0;
};

RoundTripStats RoundTrips(const PlatformModel& model, bool with_pr, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dx(-0.05, 0.05), da(-0.05, 0.05);
  FkOptions options;
  options.with_pr = with_pr;
  RoundTripStats stats;
  for (const Pose& truth : test_support::RandomWorkspacePoses(model, count, seed)) {
    const Vector6 lengths = with_pr ? model.EncoderLengths(truth) : model.LegLengths(truth);
    Pose guess = truth;
    for (int k = 0; k < 3; ++k) guess.p_BoMo_B(k) += dx(rng);
    for (int k = 0; k < 3; ++k) guess.rpy_rad(k) += da(rng);
    const FkResult fk = SolveForward(model, lengths, guess, options);
    if (!fk.ok()) {
      ++stats.failed_loudly;
      continue;
    }
    const double error = (fk.pose.ToVector() - truth.ToVector()).cwiseAbs().maxCoeff();
    stats.worst_error = std::max(stats.worst_error, error);
    if (error <= 1e-10 && fk.residual_m <= 1e-12) {
      ++stats.converged;
    } else {
      ++stats.silently_wrong;
    }
  }
  return stats;
}

// 50 000 draws find the rare pose that fails (0.1% may, loudly); the
// sanitized build looks for memory errors on the same solver in 5 000.
constexpr int kRoundTrips = test_support::kSanitizedBuild ? 5000 : 50000;

TEST(ForwardKinematics, RoundTrips50000PosesWithoutPr) {
  const PlatformModel model(Huang2021Config());
  const RoundTripStats s = RoundTrips(model, false, kRoundTrips, 31);
  EXPECT_GE(s.converged, static_cast<int>(0.999 * kRoundTrips));
  EXPECT_EQ(s.silently_wrong, 0) << "worst error " << s.worst_error;
  EXPECT_EQ(s.converged + s.failed_loudly, kRoundTrips);
  RecordProperty("failed_loudly", s.failed_loudly);
}

TEST(ForwardKinematics, RoundTrips50000PosesWithSignedPr) {
  const PlatformModel model(Huang2021Config());
  const RoundTripStats s = RoundTrips(model, true, kRoundTrips, 32);
  EXPECT_GE(s.converged, static_cast<int>(0.999 * kRoundTrips));
  EXPECT_EQ(s.silently_wrong, 0) << "worst error " << s.worst_error;
  RecordProperty("failed_loudly", s.failed_loudly);
}

TEST(ForwardKinematics, IgnoringPrMissesThePoseByThePrEffect) {
  // The same encoder lengths solved without the PR term land elsewhere: proof
  // that the PR term is really inside the solve.
  const PlatformModel model(Huang2021Config());
  Pose truth = model.home_pose();
  truth.rpy_rad.z() = 0.3;
  FkOptions no_pr;
  no_pr.with_pr = false;
  const FkResult fk = SolveForward(model, model.EncoderLengths(truth), truth, no_pr);
  ASSERT_TRUE(fk.ok());
  EXPECT_GT((fk.pose.ToVector() - truth.ToVector()).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(ForwardKinematics, RejectsNonFiniteAndNonPositiveInput) {
  const PlatformModel model(Huang2021Config());
  Vector6 lengths = model.home_length_m();
  lengths(2) = std::nan("");
  EXPECT_EQ(SolveForward(model, lengths, model.home_pose()).status, FkStatus::kInvalidInput);
  lengths(2) = -1.9;
  EXPECT_EQ(SolveForward(model, lengths, model.home_pose()).status, FkStatus::kInvalidInput);
  Pose bad_guess = model.home_pose();
  bad_guess.rpy_rad.y() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(SolveForward(model, model.home_length_m(), bad_guess).status, FkStatus::kInvalidInput);
}

TEST(ForwardKinematics, UnreachableLengthsFailInsteadOfAnswering) {
  const PlatformModel model(Huang2021Config());
  Vector6 lengths = model.home_length_m();
  lengths(0) = 6.0;  // no pose stretches one leg 4 m beyond its neighbours
  const FkResult fk = SolveForward(model, lengths, model.home_pose());
  EXPECT_FALSE(fk.ok());
  EXPECT_NE(fk.status, FkStatus::kInvalidInput);
  EXPECT_GT(fk.residual_m, 1e-3);
}

TEST(ForwardKinematics, SingularLayoutIsReportedAsSingular) {
  PlatformConfig config = Huang2021Config();  // unvalidated on purpose: all legs vertical
  config.geometry.p_BoBi_B = config.geometry.p_MoPi_M;
  const PlatformModel model(config);
  Vector6 lengths = model.home_length_m();
  lengths(0) += 0.01;
  FkOptions options;
  options.with_pr = false;
  EXPECT_EQ(SolveForward(model, lengths, model.home_pose(), options).status, FkStatus::kSingular);
}

TEST(ForwardKinematics, IterationCapIsReported) {
  const PlatformModel model(Huang2021Config());
  Pose truth = model.home_pose();
  truth.p_BoMo_B.x() = 0.3;
  FkOptions options;
  options.max_iterations = 1;
  const FkResult fk = SolveForward(model, model.EncoderLengths(truth), model.home_pose(), options);
  EXPECT_EQ(fk.status, FkStatus::kMaxIterations);
  EXPECT_STREQ(FkStatusName(fk.status), "iteration cap reached");
}

TEST(ForwardKinematics, SolutionBeyondTheJointLimitsIsNotAcceptedSilently) {
  PlatformConfig config = Huang2021Config();
  config.limits.joint_angle_max_rad = 30.0 * M_PI / 180.0;  // legs sit at ~37.6° at home
  const PlatformModel model(config);
  const FkResult fk = SolveForward(model, model.EncoderLengths(model.home_pose()), model.home_pose());
  EXPECT_EQ(fk.status, FkStatus::kOutsideWorkspace);
  EXPECT_LE(fk.residual_m, 1e-12);
}

TEST(ForwardKinematics, ConvergesQuadraticallyFromTheHomeGuess) {
  const PlatformModel model(Huang2021Config());
  Pose truth = model.home_pose();
  truth.p_BoMo_B << 0.2, -0.1, 1.7;
  truth.rpy_rad << 0.1, -0.15, 0.25;
  const FkResult fk = SolveForward(model, model.EncoderLengths(truth), model.home_pose());
  ASSERT_TRUE(fk.ok()) << FkStatusName(fk.status);
  EXPECT_LE(fk.iterations, 8);  // Newton with the exact PR derivative
  EXPECT_LT((fk.pose.ToVector() - truth.ToVector()).cwiseAbs().maxCoeff(), 1e-11);
}

}  // namespace
}  // namespace edsp
