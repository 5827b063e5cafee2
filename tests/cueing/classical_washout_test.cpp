// Classical washout as a rider and a rig engineer check it: nothing moves
// at rest, an onset is felt in its direction, a sustained force is handed
// from translation to tilt within the tilt-rate limit, and the platform
// comes back to neutral.
#include "edsp/cueing/classical_washout.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "edsp/cueing/linear_filter.h"
#include "edsp/cueing/platform_motion.h"
#include "thrown_message.h"

namespace edsp {
namespace {

constexpr double kPeriod = 1e-3;
const Vector3 kHead(0.0, 0.0, 0.8);

Pose Neutral() {
  Pose pose;
  pose.p_BoMo_B << 0.0, 0.0, 1.511;
  return pose;
}

// A sustained specific force `force` on x from t = 0.5 s for the rest of
// `seconds`, with a 0.3 s raised-cosine onset: the platform's poses.
std::vector<Pose> SustainedSurge(const ClassicalWashoutParameters& parameters, double force, double seconds) {
  ClassicalWashout washout(parameters, kPeriod);
  std::vector<Pose> poses;
  for (int k = 0; k * kPeriod <= seconds; ++k) {
    const double t = k * kPeriod;
    const double ramp = t < 0.5 ? 0.0 : t > 0.8 ? 1.0 : 0.5 * (1.0 - std::cos(kPi * (t - 0.5) / 0.3));
    VehicleSample sample;
    sample.t_s = t;
    sample.specific_force_m_s2.x() = force * ramp;
    poses.push_back(CueToPlatformPose(Neutral(), kHead, washout.Step(sample)));
  }
  return poses;
}

TEST(ClassicalWashout, ARiderAtRestIsLeftAtNeutral) {
  ClassicalWashout washout(ClassicalWashoutParameters{}, kPeriod);
  for (int k = 0; k < 5000; ++k) {
    const HeadCue cue = washout.Step(VehicleSample{});
    ASSERT_EQ(cue.position_m.norm(), 0.0);
    ASSERT_EQ(cue.rpy_rad.norm(), 0.0);
  }
}

TEST(ClassicalWashout, ASustainedBrakeIsHandedToTiltWithinTheRateLimitAndTheHeadReturns) {
  const ClassicalWashoutParameters parameters;
  const double force = -4.9;  // 0.5 g braking
  const std::vector<Pose> poses = SustainedSurge(parameters, force, 30.0);
  // Tilt never faster than its limit (the canals must not feel it), its
  // rate never stepping by more than its acceleration limit allows.
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const double rate = (poses[k].rpy_rad.y() - poses[k - 1].rpy_rad.y()) / kPeriod;
    ASSERT_LE(std::fabs(rate), parameters.tilt_rate_max_rad_s * (1.0 + 1e-9))
        << "at t = " << static_cast<double>(k) * kPeriod;
    if (k < 2) continue;
    const double before = (poses[k - 1].rpy_rad.y() - poses[k - 2].rpy_rad.y()) / kPeriod;
    ASSERT_LE(std::fabs(rate - before), parameters.tilt_accel_max_rad_s2 * kPeriod * (1.0 + 1e-6))
        << "at t = " << static_cast<double>(k) * kPeriod;
  }
  // At the end the head is back at neutral, and gravity along the tilt
  // gives the scaled force: −g sin(pitch) = k_f f.
  const Pose& last = poses.back();
  const Vector3 neutral_head = PointInBase(Neutral(), kHead);
  EXPECT_LT((PointInBase(last, kHead) - neutral_head).norm(), 1e-3);
  const VehicleSeries felt = PlatformMotionAtHead(poses, kPeriod, kHead);
  EXPECT_NEAR(felt.samples.back().specific_force_m_s2.x(), parameters.specific_force_scale * force, 1e-3);
}

TEST(ClassicalWashout, AnOnsetIsFeltInItsDirectionBeforeTiltCouldGiveIt) {
  const ClassicalWashoutParameters parameters;
  for (double force : {-3.0, 3.0}) {
    const std::vector<Pose> poses = SustainedSurge(parameters, force, 1.0);
    const VehicleSeries felt = PlatformMotionAtHead(poses, kPeriod, kHead);
    // 150 ms into the onset the tilt has turned at most 0.45 deg: the
    // force felt comes from the translation, in the vehicle's direction.
    const double felt_x = felt.samples[650].specific_force_m_s2.x();
    EXPECT_GT(felt_x * force, 0.0) << "force " << force << " felt as " << felt_x;
    EXPECT_GT(std::fabs(felt_x), 0.2 * parameters.specific_force_scale * std::fabs(force));
  }
}

TEST(ClassicalWashout, WithinItsLimitsTheTiltIsTheLowPassedForceExactly) {
  const ClassicalWashoutParameters p;
  ClassicalWashout washout(p, kPeriod);
  // The tilt's target, computed apart: the scaled force through its own low-pass.
  const double w = p.tilt_break_rad_s;
  DiscreteFilter low_pass({{w * w}, {1.0, 2.0 * p.tilt_damping * w, w * w}}, kPeriod);
  for (int k = 0; k < 20000; ++k) {
    const double fx = 0.3 * std::sin(0.7 * k * kPeriod);  // small: no limit acts
    VehicleSample sample;
    sample.specific_force_m_s2.x() = fx;
    const HeadCue cue = washout.Step(sample);
    const double target = -std::asin(low_pass.Step(p.specific_force_scale * fx) / kStandardGravity_m_s2);
    ASSERT_NEAR(cue.rpy_rad.y(), target, 1e-12) << "at t = " << k * kPeriod;
  }
  VehicleSample bad;
  bad.angular_velocity_rad_s.z() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(washout.Step(bad), std::invalid_argument);
}

TEST(ClassicalWashout, AbsurdParametersAreRefusedByName) {
  ClassicalWashoutParameters p;
  p.translation_break_rad_s.y() = 0.0;
  EXPECT_NE(test_support::ThrownMessage<std::invalid_argument>([&] {
              ClassicalWashout(p, kPeriod);
            }).find("translation_break_rad_s"),
            std::string::npos);
  p = ClassicalWashoutParameters{};
  p.specific_force_scale = 1.5;
  EXPECT_NE(test_support::ThrownMessage<std::invalid_argument>([&] {
              ClassicalWashout(p, kPeriod);
            }).find("specific_force_scale = 1.5"),
            std::string::npos);
  p = ClassicalWashoutParameters{};
  p.tilt_max_rad = 2.0;
  EXPECT_NE(
      test_support::ThrownMessage<std::invalid_argument>([&] { ClassicalWashout(p, kPeriod); }).find("tilt_max_rad"),
      std::string::npos);
}

}  // namespace
}  // namespace edsp
