// The OMCT measured in the time domain (washout, poses, the head's motion
// by finite differences) against classical washout's transfer functions
// evaluated at jω: two computations that share nothing but the parameters.
#include "edsp/cueing/omct.h"

#include <cmath>
#include <complex>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using Complex = std::complex<double>;

// What the head feels per unit input, from the washout's equations: the
// translation's s² · k s/((s² + 2ζωn s + ωn²)(s + ωb)), plus on x and y
// the tilt's gravity, k ωt²/(s² + 2ζt ωt s + ωt²); the rotation's
// s · k s/(s² + 2ζω s + ω²).
Complex Expected(const ClassicalWashoutParameters& w, int channel, double omega) {
  const Complex s(0.0, omega);
  if (channel < 3) {
    const double wn = w.translation_break_rad_s(channel), wb = w.translation_washout_rad_s(channel);
    Complex h =
        w.specific_force_scale * s * s * s / ((s * s + 2.0 * w.translation_damping * wn * s + wn * wn) * (s + wb));
    if (channel < 2) {
      const double wt = w.tilt_break_rad_s;
      h += w.specific_force_scale * wt * wt / (s * s + 2.0 * w.tilt_damping * wt * s + wt * wt);
    }
    return h;
  }
  const double wr = w.rotation_break_rad_s(channel - 3);
  return w.angular_velocity_scale * s * s / (s * s + 2.0 * w.rotation_damping * wr * s + wr * wr);
}

TEST(Omct, EveryDirectResponseIsTheWashoutsTransferFunction) {
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  for (int channel = 0; channel < kCueChannels; ++channel) {
    for (double omega : {0.251, 1.0, 3.981, 15.849}) {
      const OmctPoint p = MeasureOmct(model, config, channel, omega, OmctAmplitude(channel));
      const Complex h = Expected(config.washout, channel, omega);
      EXPECT_NEAR(p.gain, std::abs(h), 0.01 * std::abs(h) + 1e-4) << CueChannelName(channel) << " at " << omega;
      // Within 1.5°: the held input's half cycle (0.5 ms) is 0.45° at 15.85 rad/s.
      double phase_error = p.phase_deg - std::arg(h) * 180.0 / kPi;
      phase_error = std::remainder(phase_error, 360.0);
      EXPECT_LT(std::fabs(phase_error), 1.5) << CueChannelName(channel) << " at " << omega;
    }
  }
}

TEST(Omct, HeaveWashesOutAndSurgeHoldsItsScaleThroughTilt) {
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  // Heave has no tilt to hold a sustained cue: at 0.1 rad/s almost nothing
  // is felt; surge keeps the scale's worth through tilt.
  EXPECT_LT(MeasureOmct(model, config, 2, 0.1, 0.1).gain, 0.01);
  EXPECT_NEAR(MeasureOmct(model, config, 0, 0.1, 0.1).gain, config.washout.specific_force_scale, 0.02);
  EXPECT_THROW(MeasureOmct(model, config, 6, 1.0, 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
