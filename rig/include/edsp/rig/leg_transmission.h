#pragma once
// One leg's drive train as built: motor (where the encoder is) → gearbox
// (with lost motion) → screw (its real lead and once-per-turn pitch error) →
// leg length. The nominal model assumes length = zero + lead·θ/(2π·gear);
// the differences here are the effects leg_offset, lead_error,
// periodic_lead_error and backlash.
//
// Backlash: the rig is homed by extending the legs onto the reference, so at
// encoder zero the gear teeth touch on the extending flank. Extending keeps
// that contact (no error); on reversal the motor crosses the play before
// the screw follows, so a retracting leg is longer than the encoder says by
// the whole backlash.
//
// Thermal drift: the screw warms by heating_K_per_m for every metre the leg
// travels and cools towards ambient with time_constant_s; the warm part of
// the screw (screw_length_m) grows by alpha·ΔT.

#include "edsp/rig/rig_effects.h"

namespace edsp {

class LegTransmission {
 public:
  // `zero_length_m`: the nominal leg length at encoder zero (home).
  LegTransmission(int leg, double zero_length_m, const DriveParameters& drive, const RigEffects& effects);

  // The leg length for the motor's new angle `dt_s` after the last call
  // (advancing the backlash and screw-temperature states: call it in time
  // order).
  double Length(double motor_angle_rad, double dt_s = 0.0);
  double temperature_rise_K() const { return temperature_K_; }
  double screw_angle_rad() const { return driven_rad_ / gear_ratio_; }

 private:
  double zero_length_m_;
  double lead_m_;  // true lead, (1 + ε)·nominal
  double gear_ratio_;
  double play_rad_ = 0.0;  // backlash at the motor
  double periodic_m_ = 0.0, phase_rad_ = 0.0;
  double driven_rad_ = 0.0;  // gearbox output, in motor radians
  RigEffects::ThermalDrift thermal_;
  double temperature_K_ = 0.0;  // screw above ambient
  double last_travel_m_ = 0.0;
};

}  // namespace edsp
