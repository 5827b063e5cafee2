#pragma once
// The Objective Motion Cueing Test (ICAO 9625, 3rd ed.; docs/cueing.md,
// "OMCT"): the whole cueing chain in the frequency domain. A sine of one
// channel of vehicle motion (specific force or angular velocity at the
// pilot's reference point, the head here) at each of the test's twelve
// frequencies goes in; what the platform makes the head feel on the same
// channel comes out; its gain and phase against the input are the result.
// Direct responses only (x→x, …, yaw→yaw); the cross-axis ones are not
// measured yet.

#include <array>
#include <vector>

#include "edsp/cueing/cueing_config.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {

// The test's frequencies, rad/s: 0.1 to 15.85, a fifth of a decade apart.
inline constexpr std::array<double, 12> kOmctFrequencies_rad_s = {0.1,   0.158, 0.251, 0.398, 0.631, 1.0,
                                                                  1.585, 2.512, 3.981, 6.31,  10.0,  15.849};

struct OmctPoint {
  int channel = 0;  // CueChannelName's order
  double frequency_rad_s = 0.0;
  double gain = 0.0;       // output amplitude / input amplitude
  double phase_deg = 0.0;  // output's phase minus the input's, in (−180, 180]
};

// Classical washout's response on `channel` at `frequency_rad_s` to a
// sine of `amplitude` (m/s² or rad/s, small enough that no limit acts),
// from the commanded poses; measured over whole periods after the
// washout's transients have died (three periods and at least 20 s).
OmctPoint MeasureOmct(const PlatformModel& model, const CueingConfig& config, int channel, double frequency_rad_s,
                      double amplitude);

// Every channel at every frequency of the test, at the amplitudes
// OmctAmplitude gives.
std::vector<OmctPoint> RunOmct(const PlatformModel& model, const CueingConfig& config);

// The input amplitude used per channel: 0.1 m/s² (specific force), 0.02
// rad/s (angular velocity): small against the tilt-rate limit and the
// strokes, as the test's small-signal premise asks.
double OmctAmplitude(int channel);

}  // namespace edsp
