// The vestibular models against responses computed by hand (partial
// fractions of Telban & Cardullo's transfer functions).
#include "edsp/cueing/vestibular.h"

#include <cmath>

#include <gtest/gtest.h>

namespace edsp {
namespace {

// A step of `size` on one channel at t = 0, the rest at rest: [channel][k].
std::array<std::vector<double>, kCueChannels> StepOn(int channel, double size, double period_s, int samples) {
  VehicleSeries series;
  series.period_s = period_s;
  for (int k = 0; k < samples; ++k) {
    VehicleSample sample;
    sample.t_s = k * period_s;
    if (channel < 3)
      sample.specific_force_m_s2(channel) += size;
    else
      sample.angular_velocity_rad_s(channel - 3) = size;
    series.samples.push_back(sample);
  }
  return Perceive(VestibularParameters{}, series);
}

TEST(Vestibular, TheOtolithsStepResponseIsItsPartialFractions) {
  // K (τa s+1)/((τL s+1)(τS s+1)) · f0/s, K = 1:
  // f0 [1 + (τa−τL)/(τL−τS) e^{−t/τL} + (τa−τS)/(τS−τL) e^{−t/τS}].
  const OtolithParameters o;
  const double f0 = 2.0, period = 1e-3;
  const auto perceived = StepOn(0, f0, period, 20000);
  const double c1 = (o.tau_a_s - o.tau_l_s) / (o.tau_l_s - o.tau_s_s);
  const double c2 = (o.tau_a_s - o.tau_s_s) / (o.tau_s_s - o.tau_l_s);
  for (int k = 0; k < 20000; k += 97) {
    const double t = k * period;
    const double expected = f0 * (1.0 + c1 * std::exp(-t / o.tau_l_s) + c2 * std::exp(-t / o.tau_s_s));
    EXPECT_NEAR(perceived[0][static_cast<std::size_t>(k)], expected, 1e-9) << "t = " << t;
  }
  // An onset is felt larger than it is (the lead τa), then settles to it.
  EXPECT_GT(*std::max_element(perceived[0].begin(), perceived[0].end()), 1.5 * f0);
}

TEST(Vestibular, TheCanalsFeelAVelocityStepFadeAndAdaptBeyondZero) {
  // ω0 τL τa s / ((τL s+1)(τS s+1)(τa s+1)): residue at p = −1/τi is
  // −ω0 τL τa / (τi² Π_{j≠i} (1 − τj/τi)).
  const CanalParameters c;
  const double w0 = 0.2, period = 1e-3;
  const auto perceived = StepOn(5, w0, period, 60000);
  const double tau[3] = {c.tau_l_s, c.tau_s_s, c.tau_a_s};
  for (int k = 0; k < 60000; k += 131) {
    const double t = k * period;
    double expected = 0.0;
    for (int i = 0; i < 3; ++i) {
      double product = tau[i];
      for (int j = 0; j < 3; ++j) {
        if (j != i) product *= 1.0 - tau[j] / tau[i];
      }
      expected -= w0 * c.tau_l_s * c.tau_a_s / (tau[i] * product) * std::exp(-t / tau[i]);
    }
    EXPECT_NEAR(perceived[5][static_cast<std::size_t>(k)], expected, 1e-9) << "t = " << t;
  }
  // Felt almost whole at first, then it fades, and adaptation overshoots below zero.
  EXPECT_GT(perceived[5][50], 0.95 * w0);
  EXPECT_LT(perceived[5].back(), 0.0);
}

TEST(Vestibular, ARiderAtRestFeelsGravityAndNothingElse) {
  const auto perceived = StepOn(0, 0.0, 1e-3, 2000);
  for (int k = 0; k < 2000; ++k) {
    for (int channel = 0; channel < kCueChannels; ++channel) {
      ASSERT_NEAR(perceived[channel][static_cast<std::size_t>(k)], channel == 2 ? kStandardGravity_m_s2 : 0.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace edsp
