// The structural mode against the closed-form response of a damped
// oscillator: its steady state under a sinusoidal acceleration, its free
// ringing, and the inverse (mass 1 − g) a calibration applies.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "edsp/kinematics/structural_mode.h"

namespace edsp {
namespace {

// Amplitude of x for m·ẍ + 2ζω₀ẋ + ω₀²x = −A·sin(ωt), after the transient.
double SteadyAmplitude(double f0, double zeta, double f, double mass, double accel) {
  const double w0 = kTwoPi * f0, w = kTwoPi * f;
  return accel / std::hypot(w0 * w0 - mass * w * w, 2.0 * zeta * w0 * w);
}

double MeasuredAmplitude(double f0, double zeta, double f, double mass, double dt) {
  StructuralMode mode(f0, zeta, Vector3::Constant(mass));
  double peak = 0.0;
  const double settle = 60.0 / (zeta * kTwoPi * f0);  // many decay times
  for (double t = 0.0; t < settle + 3.0 / f; t += dt) {
    const double x = mode.Advance(t == 0.0 ? 0.0 : dt, Vector3::Constant(std::sin(kTwoPi * f * t))).x();
    if (t > settle) peak = std::max(peak, std::abs(x));
  }
  return peak;
}

TEST(StructuralMode, FollowsTheOscillatorsSteadyStateBelowAtAndAboveResonance) {
  for (double f : {1.0, 4.8, 5.0, 12.0}) {
    const double expected = SteadyAmplitude(5.0, 0.05, f, 1.0, 1.0);
    EXPECT_NEAR(MeasuredAmplitude(5.0, 0.05, f, 1.0, 1e-3), expected, 0.01 * expected) << f << " Hz";
    // At a tracker's 100 Hz the same (the acceleration linear in between; the
    // peak of a 12 Hz sine sampled at 100 Hz is up to 4% under its own).
    EXPECT_NEAR(MeasuredAmplitude(5.0, 0.05, f, 1.0, 1e-2), expected, 0.05 * expected) << f << " Hz, 100 Hz";
  }
}

TEST(StructuralMode, ALighterMassRingsHigher) {
  // Mass 1 − g moves the resonance to f0/√(1 − g): the inverse a calibration runs.
  const double f = 5.0 / std::sqrt(0.6);
  const double expected = SteadyAmplitude(5.0, 0.05, f, 0.6, 1.0);
  EXPECT_NEAR(MeasuredAmplitude(5.0, 0.05, f, 0.6, 1e-3), expected, 0.01 * expected);
}

TEST(StructuralMode, RingsFreelyAtItsDampedFrequencyAndStartsAgainAfterAGap) {
  StructuralMode mode(4.0, 0.02);
  mode.Advance(0.0, Vector3::Zero());
  mode.Advance(0.001, Vector3::UnitX());  // a 1 ms kick of 1 m/s²
  mode.Advance(0.001, Vector3::Zero());
  double last = mode.sway().x(), t = 0.002, previous_crossing = -1.0, period = 0.0;
  for (int k = 0; k < 5000; ++k, t += 1e-4) {
    const double x = mode.Advance(1e-4, Vector3::Zero()).x();
    if (last < 0.0 && x >= 0.0) {
      if (previous_crossing > 0.0) period = t - previous_crossing;
      previous_crossing = t;
    }
    last = x;
  }
  const double damped_hz = 4.0 * std::sqrt(1.0 - 0.02 * 0.02);
  EXPECT_NEAR(1.0 / period, damped_hz, 0.002 * damped_hz);
  mode.Advance(60.0, Vector3::UnitY());     // ζω = 0.5/s: rung out to 1e-4 in 18 s
  EXPECT_EQ(mode.sway(), Vector3::Zero());  // rung out over the gap
  mode.Advance(0.01, Vector3::UnitY());
  mode.Advance(-0.5, Vector3::UnitY());  // time went back: a new session
  EXPECT_EQ(mode.sway(), Vector3::Zero());
}

TEST(StructuralMode, RefusesAModeItCannotIntegrate) {
  EXPECT_THROW(StructuralMode(0.0, 0.03), std::invalid_argument);
  EXPECT_THROW(StructuralMode(std::nan(""), 0.03), std::invalid_argument);
  EXPECT_THROW(StructuralMode(5.0, 2.0), std::invalid_argument);
  EXPECT_THROW(StructuralMode(5.0, 0.03, Vector3(1.0, 0.0, 1.0)), std::invalid_argument);
  // A light mass (a calibration's inverse of a gain of 0.75) stays stable at 1 kHz.
  StructuralMode light(25.0, 1.0, Vector3::Constant(0.25));
  for (int k = 0; k < 2000; ++k) light.Advance(k == 0 ? 0.0 : 1e-3, Vector3::Constant(k < 100 ? 1.0 : 0.0));
  EXPECT_TRUE(light.sway().allFinite());
  EXPECT_LT(light.sway().norm(), 1e-3);
}

}  // namespace
}  // namespace edsp
