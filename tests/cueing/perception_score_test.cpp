// The perception score: nothing between identical motions, the delay of a
// late copy found, and errors in thresholds.
#include "edsp/cueing/perception_score.h"

#include <cmath>

#include <gtest/gtest.h>

namespace edsp {
namespace {

VehicleSeries Wobble(double delay_s, double scale) {
  VehicleSeries series;
  series.period_s = 1e-3;
  for (int k = 0; k < 8000; ++k) {
    const double t = k * series.period_s - delay_s;
    VehicleSample sample;
    sample.t_s = k * series.period_s;
    if (t > 0.0) {
      sample.specific_force_m_s2.y() += scale * (std::sin(2.1 * t) + 0.5 * std::sin(7.3 * t));
      sample.angular_velocity_rad_s.z() = scale * 0.1 * std::sin(3.7 * t);
    }
    series.samples.push_back(sample);
  }
  return series;
}

TEST(PerceptionScore, IdenticalMotionsAreFeltAlike) {
  const PerceptionScore score = ScorePerception(VestibularParameters{}, Wobble(0.0, 1.0), Wobble(0.0, 1.0));
  EXPECT_EQ(score.overall, 0.0);
  EXPECT_NEAR(score.channels[1].correlation, 1.0, 1e-12);
  EXPECT_EQ(score.channels[1].delay_s, 0.0);
  EXPECT_EQ(score.channels[0].correlation, 0.0);  // a channel that never moves
}

TEST(PerceptionScore, ALateCopyIsFoundLateByItsDelay) {
  const PerceptionScore score = ScorePerception(VestibularParameters{}, Wobble(0.0, 1.0), Wobble(0.12, 1.0));
  EXPECT_NEAR(score.channels[1].delay_s, 0.12, 0.002);
  EXPECT_NEAR(score.channels[5].delay_s, 0.12, 0.002);
  EXPECT_GT(score.overall, 0.0);
}

TEST(PerceptionScore, HalfTheMotionIsHalfItsPerceptionOffInThresholds) {
  const VestibularParameters parameters;
  const auto vehicle = Wobble(0.0, 1.0);
  const PerceptionScore score = ScorePerception(parameters, vehicle, Wobble(0.0, 0.5));
  // Linear models: the error is the perceived half of the motion.
  const auto felt = Perceive(parameters, vehicle);
  double sum = 0.0;
  for (double v : felt[1]) sum += 0.25 * v * v;
  const double expected = std::sqrt(sum / static_cast<double>(felt[1].size()));
  EXPECT_NEAR(score.channels[1].rms_error, expected, 1e-9);
  EXPECT_NEAR(score.channels[1].in_thresholds, expected / parameters.otolith.threshold_m_s2.y(), 1e-9);
  EXPECT_NEAR(score.channels[1].correlation, 1.0, 1e-9);
}

TEST(PerceptionScore, SeriesOfDifferentLengthsOrRatesAreRefused) {
  VehicleSeries shorter = Wobble(0.0, 1.0);
  shorter.samples.pop_back();
  EXPECT_THROW(ScorePerception(VestibularParameters{}, Wobble(0.0, 1.0), shorter), std::invalid_argument);
  VehicleSeries slower = Wobble(0.0, 1.0);
  slower.period_s = 2e-3;
  EXPECT_THROW(ScorePerception(VestibularParameters{}, Wobble(0.0, 1.0), slower), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
