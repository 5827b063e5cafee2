#pragma once
// A session of edsp's stack on the virtual rig (sim/offline_run.h) as the
// diagnosis' tests run it: the paper's motions at 0.25 m/s and 0.5 rad/s,
// the tracker at 100 Hz in a frame of its own; and the rig a calibration
// is tested on, leg offsets, backlash and lead errors behind a drive with
// integral action.

#include <cstdint>
#include <string>
#include <vector>

#include "edsp/sim/offline_run.h"

namespace edsp::test_support {

inline OfflineRunOptions OfflineSession(const std::vector<std::string>& motions, int stops, double dwell_s,
                                        double noise_m, std::uint64_t seed, const Pose& X_TB,
                                        const std::string& out_dir) {
  OfflineRunOptions o;
  o.motions = motions;
  o.paper.stops = stops;
  o.paper.dwell_s = dwell_s;
  o.paper.max_speed_m_s = 0.25;
  o.paper.max_speed_rad_s = 0.5;
  o.tracker.noise_sigma_m = noise_m;
  o.tracker.rate_hz = 100.0;
  o.tracker.seed = seed;
  o.tracker.X_TB = X_TB;
  o.out_dir = out_dir;
  return o;
}

inline RigEffects OffsetsBacklashAndLead() {
  RigEffects fx;
  fx.servo_lag.integral_time_s = 0.05;
  fx.leg_offset.enabled = fx.backlash.enabled = fx.lead_error.enabled = true;
  fx.leg_offset.offset_m = {80e-6, -60e-6, 40e-6, -100e-6, 50e-6, -20e-6};
  fx.backlash.backlash_m = {20e-6, 25e-6, 22e-6, 30e-6, 18e-6, 26e-6};
  fx.lead_error.epsilon = {1.5e-4, -1e-4, 2e-4, 0.5e-4, -1.5e-4, 1e-4};
  return fx;
}

}  // namespace edsp::test_support
