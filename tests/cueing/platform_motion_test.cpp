// What a head on a moving platform feels, against motions whose specific
// force and angular velocity are known in closed form.
#include "edsp/cueing/platform_motion.h"

#include <cmath>

#include <gtest/gtest.h>

namespace edsp {
namespace {

TEST(PlatformMotion, AHeadOnATiltedPlatformFeelsGravityAlongItsTilt) {
  Pose tilted;
  tilted.p_BoMo_B << 0.0, 0.0, 1.5;
  tilted.rpy_rad << 0.1, -0.2, 0.3;
  const VehicleSeries felt = PlatformMotionAtHead(std::vector<Pose>(5, tilted), 1e-3, Vector3(0.1, 0.2, 0.8));
  // Rᵀ (0, 0, g), written out for Rz(yaw)·Ry(pitch)·Rx(roll).
  const double r = 0.1, p = -0.2, g = kStandardGravity_m_s2;
  const Vector3 expected(-g * std::sin(p), g * std::cos(p) * std::sin(r), g * std::cos(p) * std::cos(r));
  for (const VehicleSample& sample : felt.samples) {
    EXPECT_LT((sample.specific_force_m_s2 - expected).norm(), 1e-9);
    EXPECT_LT(sample.angular_velocity_rad_s.norm(), 1e-12);
  }
}

TEST(PlatformMotion, AHeadOffTheYawAxisFeelsTheTurnAndItsCentripetalForce) {
  const double rate = 0.4, period = 1e-3;
  const Vector3 head(0.3, 0.0, 0.8);
  std::vector<Pose> poses(2000);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    poses[k].p_BoMo_B << 0.0, 0.0, 1.5;
    poses[k].rpy_rad << 0.0, 0.0, rate * static_cast<double>(k) * period;
  }
  const VehicleSeries felt = PlatformMotionAtHead(poses, period, head);
  for (std::size_t k = 0; k < poses.size(); k += 101) {
    const VehicleSample& sample = felt.samples[k];
    EXPECT_NEAR(sample.angular_velocity_rad_s.z(), rate, 1e-9);
    EXPECT_NEAR(sample.angular_velocity_rad_s.head<2>().norm(), 0.0, 1e-9);
    // Centripetal: −ω² r towards the axis, along the head's own x.
    EXPECT_NEAR(sample.specific_force_m_s2.x(), -rate * rate * head.x(), 1e-6);
    EXPECT_NEAR(sample.specific_force_m_s2.y(), 0.0, 1e-6);
    EXPECT_NEAR(sample.specific_force_m_s2.z(), kStandardGravity_m_s2, 1e-6);
  }
}

TEST(PlatformMotion, ASurgingPlatformIsFeltAsItsSecondDerivative) {
  const double amplitude = 0.05, frequency = 1.5, period = 1e-3, w = 2.0 * kPi * frequency;
  std::vector<Pose> poses(3000);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    poses[k].p_BoMo_B << amplitude * std::sin(w * static_cast<double>(k) * period), 0.0, 1.5;
  }
  const VehicleSeries felt = PlatformMotionAtHead(poses, period, Vector3(0.0, 0.0, 0.8));
  for (std::size_t k = 1; k + 1 < poses.size(); k += 53) {
    const double expected = -amplitude * w * w * std::sin(w * static_cast<double>(k) * period);
    // Central differences: relative error (ωT)²/12.
    EXPECT_NEAR(felt.samples[k].specific_force_m_s2.x(), expected, 1e-4 * amplitude * w * w);
  }
}

TEST(PlatformMotion, TooFewPosesAreRefused) {
  EXPECT_THROW(PlatformMotionAtHead(std::vector<Pose>(2), 1e-3, Vector3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
