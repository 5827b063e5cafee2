#include "edsp/cueing/random_vehicle.h"

#include <algorithm>
#include <cmath>

namespace edsp {
namespace {
// What the vehicle packet accepts (vehicle_packet.h), kept inside.
constexpr double kForceLimit_m_s2 = 4.0 * kStandardGravity_m_s2;
constexpr double kAngularVelocityLimit_rad_s = kPi;
}  // namespace

RandomVehicle::RandomVehicle(const RandomVehicleParameters& parameters, double period_s, std::uint64_t seed)
    : parameters_(parameters),
      period_s_(period_s),
      pole_(std::exp(-kTwoPi * parameters.bandwidth_hz * period_s)),
      drive_(std::sqrt(1.0 - pole_ * pole_)),
      // x2[k] = a x2[k−1] + (1 − a) x1[k] of a unit-variance AR(1) x1 of
      // the same pole has the variance (1 + a²)/(1 + a)².
      scale_((1.0 + pole_) / std::sqrt(1.0 + pole_ * pole_)),
      random_(seed) {}

VehicleSample RandomVehicle::Next() {
  VehicleSample sample;
  sample.t_s = static_cast<double>(step_++) * period_s_;
  for (int channel = 0; channel < kCueChannels; ++channel) {
    // x1[k] = a x1[k−1] + √(1 − a²) w[k]: unit variance in steady state.
    double& first = first_[channel];
    double& second = second_[channel];
    first = pole_ * first + drive_ * normal_(random_);
    second = pole_ * second + (1.0 - pole_) * first;
    const double x = scale_ * second;
    if (channel < 3) {
      sample.specific_force_m_s2(channel) +=
          std::clamp(parameters_.force_rms_m_s2(channel) * x, -kForceLimit_m_s2, kForceLimit_m_s2);
    } else {
      sample.angular_velocity_rad_s(channel - 3) =
          std::clamp(parameters_.angular_velocity_rms_rad_s(channel - 3) * x, -kAngularVelocityLimit_rad_s,
                     kAngularVelocityLimit_rad_s);
    }
  }
  return sample;
}

}  // namespace edsp
