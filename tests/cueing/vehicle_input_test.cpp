// The vehicle's input as the cueing sees it: stale and repeated packets
// refused, a lost input faded to rest with no step, and the platform
// washed home from a sustained cue inside every limit.
#include "edsp/cueing/vehicle_input.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "edsp/cueing/classical_washout.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/path_check.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

VehiclePacket Packet(std::uint32_t sequence, double time_s, double fx) {
  VehiclePacket p;
  p.sequence = sequence;
  p.time_s = time_s;
  p.specific_force_m_s2.x() = fx;
  return p;
}

TEST(VehicleInput, StaleRepeatedAndBackwardPacketsAreRefused) {
  VehicleInput input(VehicleInputParameters{});
  EXPECT_EQ(input.state(0.0), VehicleInputState::kWaiting);
  EXPECT_FALSE(input.Accept(Packet(41, 1.0, 0.0), 0.0));
  EXPECT_EQ(input.Accept(Packet(41, 1.1, 0.0), 0.01).value_or(""), "sequence 41 after 41: out of order or repeated");
  EXPECT_EQ(input.Accept(Packet(40, 1.1, 0.0), 0.01).value_or(""), "sequence 40 after 41: out of order or repeated");
  EXPECT_EQ(input.Accept(Packet(42, 0.9, 0.0), 0.01).value_or(""), "time_s 0.9 after 1: the vehicle's time went back");
  EXPECT_FALSE(input.Accept(Packet(45, 1.2, 0.0), 0.02));
  EXPECT_EQ(input.missed_packets(), 3u);
  // Across the sequence's wrap.
  VehicleInput wrapping(VehicleInputParameters{});
  EXPECT_FALSE(wrapping.Accept(Packet(0xFFFFFFFFu, 1.0, 0.0), 0.0));
  EXPECT_FALSE(wrapping.Accept(Packet(0, 1.001, 0.0), 0.001));
  EXPECT_EQ(wrapping.missed_packets(), 0u);
}

TEST(VehicleInput, AFrozenVehicleARestartedOneAndBadParametersAreHandled) {
  VehicleInput input(VehicleInputParameters{});
  EXPECT_FALSE(input.Accept(Packet(7, 5.0, 0.0), 0.0));
  EXPECT_FALSE(input.Accept(Packet(8, 5.0, 0.0), 0.01));  // paused: its time stands
  // The vehicle model restarted while the input was live: refused...
  EXPECT_TRUE(input.Accept(Packet(1, 0.0, 0.0), 0.02));
  // ...and, once the input is lost, a new stream.
  EXPECT_EQ(input.state(0.5), VehicleInputState::kLost);
  EXPECT_FALSE(input.Accept(Packet(1, 0.0, 0.0), 0.5));
  EXPECT_EQ(input.state(0.5), VehicleInputState::kLive);
  // Gaps counted across the wrap.
  VehicleInput wrapping(VehicleInputParameters{});
  EXPECT_FALSE(wrapping.Accept(Packet(0xFFFFFFFEu, 1.0, 0.0), 0.0));
  EXPECT_FALSE(wrapping.Accept(Packet(2, 1.1, 0.0), 0.01));
  EXPECT_EQ(wrapping.missed_packets(), 3u);
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    VehicleInputParameters p;
    p.fade_s = bad;
    EXPECT_THROW(VehicleInput{p}, std::invalid_argument) << bad;
    p = VehicleInputParameters{};
    p.timeout_s = bad;
    EXPECT_THROW(VehicleInput{p}, std::invalid_argument) << bad;
  }
}

TEST(VehicleInput, ALostInputFadesToRestWithoutAStepAndFadesBackIn) {
  const VehicleInputParameters parameters;  // 0.1 s timeout, 1 s fade
  VehicleInput input(parameters);
  const double fx = -4.9, period = 1e-3;
  std::uint32_t sequence = 0;
  double previous = 0.0;
  const double step_bound = kPi / 2.0 * std::fabs(fx) / parameters.fade_s * period * 1.001;
  for (int k = 0; k <= 8000; ++k) {
    const double t = k * period;
    // Packets at 100 Hz up to 2 s, none until 5 s, then again.
    if ((t < 2.0 || t >= 5.0) && k % 10 == 0) {
      ASSERT_FALSE(input.Accept(Packet(++sequence, t, fx), t));
    }
    const double now = input.At(t).specific_force_m_s2.x();
    if (k > 0) {
      ASSERT_LE(std::fabs(now - previous), step_bound) << "a step at t = " << t;
    }
    previous = now;
    if (t > 0.2 && t < 2.0) {
      ASSERT_EQ(input.state(t), VehicleInputState::kLive);
    }
    if (t > 1.2 && t < 2.08) {
      ASSERT_EQ(now, fx) << t;  // faded in, then live
    }
    if (t > 3.2 && t < 5.0) {
      ASSERT_EQ(input.state(t), VehicleInputState::kLost);
      ASSERT_EQ(now, 0.0) << t;  // at rest
    }
    if (t > 6.1) {
      ASSERT_EQ(now, fx) << t;
    }
  }
  EXPECT_EQ(input.At(8.0).specific_force_m_s2.z(), kStandardGravity_m_s2);
}

TEST(VehicleInput, AVehicleLostMidBrakeIsWashedHomeInsideEveryLimit) {
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const double period = 1.0 / config.rate_hz;
  VehicleInput input(config.input);
  ClassicalWashout washout(config.washout, period);
  std::vector<Pose> poses;
  std::uint32_t sequence = 0;
  for (int k = 0; k * period <= 40.0; ++k) {
    const double t = k * period;
    // 0.5 g braking, ramped in over 0.5 s; the vehicle falls silent at 3 s.
    const double ramp = std::min(1.0, std::max(0.0, (t - 1.0) / 0.5));
    if (t < 3.0 && k % 4 == 0) {
      ASSERT_FALSE(input.Accept(Packet(++sequence, t, -4.9 * ramp), t));
    }
    poses.push_back(CueToPlatformPose(model.home_pose(), config.head_in_platform_m, washout.Step(input.At(t))));
  }
  const PathCheck check = CheckPath(
      model, PathLimitsOf(model),
      [&](double t) {
        return poses[std::min(poses.size() - 1, static_cast<std::size_t>(std::llround(t / period)))].ToVector();
      },
      static_cast<double>(poses.size() - 1) * period, config.rate_hz);
  EXPECT_TRUE(check.ok()) << check.Describe();
  const Pose& last = poses.back();
  EXPECT_LT((last.p_BoMo_B - model.home_pose().p_BoMo_B).norm(), 1e-3);
  EXPECT_LT(last.rpy_rad.norm(), 1e-3);
  // The tilt the brake built was real, and was taken back.
  double deepest = 0.0;
  for (const Pose& pose : poses) deepest = std::max(deepest, pose.rpy_rad.y());
  EXPECT_GT(deepest, 0.05);
}

}  // namespace
}  // namespace edsp
