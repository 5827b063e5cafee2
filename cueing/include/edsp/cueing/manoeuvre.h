#pragma once
// A vehicle manoeuvre described in a file (config/manoeuvres/*.toml;
// docs/cueing.md, "Manoeuvres"): what the vehicle makes the rider feel,
// as the sum of smooth pulses and sines on the six channels over gravity
// at rest. A file says what it is; the same file drives the offline runs,
// the benchmark and the live tests, so a figure can always be traced to
// the motion that produced it.

#include <string>
#include <vector>

#include "edsp/config_file/config_error.h"
#include "edsp/cueing/vehicle_motion.h"

namespace edsp {

// Raised-cosine rise, hold, raised-cosine fall: no step in the channel.
struct CuePulse {
  int channel = 0;
  double start_s = 0.0, rise_s = 0.0, hold_s = 0.0, fall_s = 0.0;
  double amplitude = 0.0;  // m/s² or rad/s
};

// amplitude·sin(2π f (t − start) + phase), faded in and out over fade_s.
struct CueSine {
  int channel = 0;
  double start_s = 0.0, duration_s = 0.0, fade_s = 0.0;
  double amplitude = 0.0, frequency_hz = 0.0, phase_rad = 0.0;
};

struct Manoeuvre {
  std::string name;
  std::string description;
  std::string origin;  // the file it came from
  double duration_s = 0.0;
  std::vector<CuePulse> pulses;
  std::vector<CueSine> sines;

  VehicleSample At(double t_s) const;
};

// Throws ConfigError naming the file, the line and the key.
Manoeuvre LoadManoeuvre(const std::string& path);
Manoeuvre ParseManoeuvre(const std::string& toml_text, const std::string& origin);

// The manoeuvre sampled at `period_s` over [0, duration_s].
VehicleSeries SampleManoeuvre(const Manoeuvre& manoeuvre, double period_s);

}  // namespace edsp
