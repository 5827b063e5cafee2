#include "edsp/rig/leg_transmission.h"

#include <cmath>

namespace edsp {

LegTransmission::LegTransmission(int leg, double zero_length_m, const DriveParameters& drive, const RigEffects& effects)
    : zero_length_m_(zero_length_m), lead_m_(drive.lead_m), gear_ratio_(drive.gear_ratio) {
  const auto i = static_cast<std::size_t>(leg);
  if (effects.leg_offset.enabled) zero_length_m_ += effects.leg_offset.offset_m[i];
  if (effects.lead_error.enabled) lead_m_ *= 1.0 + effects.lead_error.epsilon[i];
  if (effects.backlash.enabled) {
    play_rad_ = effects.backlash.backlash_m[i] / drive.lead_m * kTwoPi * drive.gear_ratio;
  }
  if (effects.periodic_lead_error.enabled) {
    periodic_m_ = effects.periodic_lead_error.amplitude_m[i];
    phase_rad_ = effects.periodic_lead_error.phase_rad[i];
  }
  driven_rad_ = -play_rad_;  // homed extending: in contact on the extending flank
  if (effects.thermal_drift.enabled) thermal_ = effects.thermal_drift;
}

double LegTransmission::Length(double motor_angle_rad, double dt_s) {
  // The output stays put until the motor has crossed the play.
  if (motor_angle_rad - driven_rad_ > play_rad_) driven_rad_ = motor_angle_rad - play_rad_;
  if (driven_rad_ - motor_angle_rad > 0.0) driven_rad_ = motor_angle_rad;
  const double screw = (driven_rad_ + play_rad_) / gear_ratio_;  // zero at home
  const double travel = lead_m_ * screw / kTwoPi;
  if (thermal_.enabled) {
    temperature_K_ +=
        thermal_.heating_K_per_m * std::abs(travel - last_travel_m_) - temperature_K_ * dt_s / thermal_.time_constant_s;
    last_travel_m_ = travel;
  }
  return zero_length_m_ + travel + periodic_m_ * (std::sin(screw + phase_rad_) - std::sin(phase_rad_)) +
         thermal_.alpha_per_K * temperature_K_ * thermal_.screw_length_m * (thermal_.enabled ? 1.0 : 0.0);
}

}  // namespace edsp
