// A live run's score from stamped streams, against motion worked out by
// hand: a platform surging along a sine, whose head feels −Aω² sin ωt (no
// rotation: the platform's acceleration), heard at 250 Hz as a vehicle
// would send it; the commanded poses at 1 kHz on a clock of their own, the
// real ones the same 20 ms later. The score puts each on one grid by its
// stamps: the commanded motion feels like the vehicle, the real one lags
// it by the 20 ms.
#include "edsp/cueing/live_score.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

constexpr double kAmplitude_m = 0.05;
constexpr double kOmega_rad_s = 2.0 * kPi * 0.5;
constexpr std::int64_t kStart = 1'800'000'000'000'000;
constexpr double kSeconds = 8.0;

Vector6 Surge(double t_s) {
  Vector6 pose = Vector6::Zero();
  pose(0) = kAmplitude_m * std::sin(kOmega_rad_s * t_s);
  pose(2) = 1.5;
  return pose;
}

std::vector<StampedPose> Poses(std::int64_t offset_us, double lag_s, std::int64_t period_us = 1000) {
  std::vector<StampedPose> poses;
  for (std::int64_t t = offset_us; t <= static_cast<std::int64_t>(kSeconds * 1e6); t += period_us) {
    poses.push_back({kStart + t, Surge(static_cast<double>(t) * 1e-6 - lag_s)});
  }
  return poses;
}

std::vector<HeardVehicleSample> Vehicle() {
  std::vector<HeardVehicleSample> heard;
  for (std::int64_t t = 0; t <= static_cast<std::int64_t>(kSeconds * 1e6); t += 4000) {
    const double s = static_cast<double>(t) * 1e-6;
    HeardVehicleSample sample;
    sample.utime = kStart + t;
    sample.specific_force_m_s2 =
        Vector3(-kAmplitude_m * kOmega_rad_s * kOmega_rad_s * std::sin(kOmega_rad_s * s), 0.0, 9.80665);
    heard.push_back(sample);
  }
  return heard;
}

CueingConfig Config() { return LoadCueingConfig(SourceDir() + "/config/cueing.toml"); }

TEST(LiveScore, TheCommandedMotionFeelsLikeTheVehicleAndTheRealOneLagsByItsDelay) {
  const LiveCueingScore s = ScoreLiveCueing(Config(), Vehicle(), Poses(300, 0.0), Poses(300, 0.020));
  EXPECT_NEAR(s.duration_s, kSeconds - 1e-3, 1e-3);  // from the first pose to the last one
  const ChannelScore& fx = s.commanded.channels[0];
  EXPECT_GT(fx.correlation, 0.99);
  EXPECT_LE(fx.delay_s, 0.004) << "the 250 Hz samples held: 2 ms on average";
  ASSERT_TRUE(s.real.has_value());
  const ChannelScore& real_fx = s.real->channels[0];
  EXPECT_NEAR(real_fx.delay_s - fx.delay_s, 0.020, 0.002);
  EXPECT_GT(real_fx.rms_error, 2.0 * fx.rms_error);
  for (int channel = 1; channel < kCueChannels; ++channel) {
    EXPECT_LT(s.commanded.channels[channel].rms_error, 1e-3) << CueChannelName(channel) << ": nothing else moves";
  }
}

// A real rig's pose from its encoders comes at 100 Hz: scored as the same
// motion at 1 kHz is, not as a string of steps in acceleration.
TEST(LiveScore, PosesAt100HzFeelAsTheSameMotionAt1kHz) {
  const LiveCueingScore s = ScoreLiveCueing(Config(), Vehicle(), Poses(300, 0.0), Poses(0, 0.0, 10'000));
  ASSERT_TRUE(s.real.has_value());
  const ChannelScore &commanded = s.commanded.channels[0], &real = s.real->channels[0];
  EXPECT_GT(real.correlation, 0.99);
  EXPECT_NEAR(real.delay_s, commanded.delay_s, 1e-3);
  // Straight lines between the poses fail it: their acceleration comes in spikes at the poses.
  EXPECT_NEAR(real.rms_error, commanded.rms_error, 0.1 * commanded.rms_error);
}

TEST(LiveScore, RealPosesThatDoNotSpanTheRunAreNotScoredAndNoOverlapIsSaid) {
  std::vector<StampedPose> real = Poses(300, 0.0);
  real.resize(real.size() / 2);
  EXPECT_FALSE(ScoreLiveCueing(Config(), Vehicle(), Poses(300, 0.0), real).real.has_value());
  EXPECT_THROW(ScoreLiveCueing(Config(), {}, Poses(300, 0.0), {}), std::invalid_argument);
  std::vector<HeardVehicleSample> before = Vehicle();
  for (HeardVehicleSample& h : before) h.utime -= 100'000'000;  // heard in another run
  try {
    ScoreLiveCueing(Config(), before, Poses(300, 0.0), {});
    ADD_FAILURE() << "scored streams that never overlap";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("heard for 0.000 s"), std::string::npos) << e.what();
  }
}

TEST(LiveScore, ASilenceTheCueingTookForALostInputEndsWhatIsScored) {
  std::vector<HeardVehicleSample> heard;
  for (const HeardVehicleSample& h : Vehicle()) {
    const double t = static_cast<double>(h.utime - kStart) * 1e-6;
    if (t < 2.0 || t > 2.5) heard.push_back(h);  // silent for 0.5 s, over the 0.1 s timeout
  }
  const LiveCueingScore s = ScoreLiveCueing(Config(), heard, Poses(300, 0.0), {});
  EXPECT_NEAR(s.duration_s, kSeconds - 2.5, 5e-3) << "the longer stretch heard, after the silence";
  EXPECT_EQ(s.start_utime, heard[static_cast<std::size_t>(2.0 / 0.004)].utime);
}

}  // namespace
}  // namespace edsp
