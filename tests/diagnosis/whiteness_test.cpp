// The whiteness test of the residual: white noise passes, a correlated
// (AR(1)) residual fails, as MATLAB's resid would show.
#include <random>

#include <gtest/gtest.h>

#include "edsp/diagnosis/whiteness.h"

namespace edsp::gap {
namespace {

Design Blocks(int runs, int samples) {
  Design d;
  for (int r = 0; r < runs; ++r) d.run_samples.push_back({r * samples, samples});
  d.sample_run.resize(static_cast<std::size_t>(runs * samples));
  return d;
}

TEST(Whiteness, WhiteNoisePassesAndCorrelatedResidualFails) {
  const Design d = Blocks(3, 2000);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd white(3 * 6000), ar(3 * 6000);
  double state[3] = {0, 0, 0};
  for (int k = 0; k < 6000; ++k) {
    for (int a = 0; a < 3; ++a) {
      white(3 * k + a) = n(rng);
      state[a] = 0.5 * state[a] + n(rng);
      ar(3 * k + a) = state[a];
    }
  }
  const Whiteness w = TestWhiteness(d, white);
  EXPECT_TRUE(w.white) << w.q << " > " << w.threshold;
  EXPECT_NEAR(w.lag1, 0.0, 0.05);
  const Whiteness c = TestWhiteness(d, ar);
  EXPECT_FALSE(c.white);
  EXPECT_NEAR(c.lag1, 0.5, 0.05);
  EXPECT_GT(c.outside_fraction, 0.1);
}

}  // namespace
}  // namespace edsp::gap
