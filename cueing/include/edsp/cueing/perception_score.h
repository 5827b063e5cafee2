#pragma once
// How far what the platform makes a rider feel is from what the vehicle
// would: both motions through the same vestibular models, then per
// channel the RMS of the perceived difference, their correlation and the
// delay that best lines them up. `overall` puts the six on one scale:
// the RMS over channels of each channel's RMS error in units of its
// perception threshold (docs/cueing.md, "Perception score").

#include <array>
#include <string>

#include "edsp/cueing/vestibular.h"

namespace edsp {

struct ChannelScore {
  double rms_error = 0.0;      // m/s² or rad/s
  double correlation = 0.0;    // Pearson's, of the perceived signals; 0 if either is constant
  double delay_s = 0.0;        // the platform's lag that maximises the correlation (0..max_delay)
  double in_thresholds = 0.0;  // rms_error / the channel's threshold
};

struct PerceptionScore {
  std::array<ChannelScore, kCueChannels> channels;
  double overall = 0.0;
};

// `vehicle` and `platform` at one period and of one length (throws
// std::invalid_argument naming what differs).
PerceptionScore ScorePerception(const VestibularParameters& parameters, const VehicleSeries& vehicle,
                                const VehicleSeries& platform, double max_delay_s = 0.5);

}  // namespace edsp
