#pragma once
// Random vehicle motion: what a soak of the cueing feeds it. Each channel
// is Gaussian noise low-passed to `bandwidth_hz` twice (two first-order
// stages: a vehicle's motion has a bounded rate of change, which white
// noise through one stage has not) at its own RMS, clamped to what the
// vehicle packet accepts: a driver thrown around a rough track, seeded so
// a run can be repeated.

#include <cstdint>
#include <random>

#include "edsp/cueing/vehicle_motion.h"

namespace edsp {

struct RandomVehicleParameters {
  double bandwidth_hz = 2.0;
  Vector3 force_rms_m_s2 = Vector3(3.0, 3.0, 2.0);
  Vector3 angular_velocity_rms_rad_s = Vector3(0.3, 0.3, 0.3);
};

class RandomVehicle {
 public:
  RandomVehicle(const RandomVehicleParameters& parameters, double period_s, std::uint64_t seed);
  VehicleSample Next();

 private:
  RandomVehicleParameters parameters_;
  double period_s_;
  double pole_;   // e^{−2π f T}
  double drive_;  // the white noise's gain that gives the first stage unit RMS
  double scale_;  // the second stage's gain back to unit RMS
  std::mt19937_64 random_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  double first_[kCueChannels] = {};
  double second_[kCueChannels] = {};
  std::int64_t step_ = 0;
};

}  // namespace edsp
