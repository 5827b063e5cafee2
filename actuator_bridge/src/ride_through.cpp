#include "edsp/actuator_bridge/ride_through.h"

#include <algorithm>
#include <cmath>

namespace edsp {

double StopTimeS(const DriveSetpoint& command, double leg_m_per_rad, double decel_m_s2) {
  double fastest_rad_s = 0.0;
  for (const double w : command.motor_velocity_rad_s) fastest_rad_s = std::max(fastest_rad_s, std::abs(w));
  return decel_m_s2 > 0.0 ? fastest_rad_s * std::abs(leg_m_per_rad) / decel_m_s2 : 0.0;
}

DriveSetpoint RideThroughSetpoint(const DriveSetpoint& command, const RideThrough& ride, double silent_s) {
  // Travel and speed as fractions of the feed-forward's: 1 per second while
  // continued, then a linear ramp of the speed to 0 over stop_s.
  const double ramp_s = std::clamp(silent_s - ride.continue_s, 0.0, ride.stop_s);
  const double continued_s = std::clamp(silent_s, 0.0, ride.continue_s);
  const double speed = ride.stop_s > 0.0 ? 1.0 - ramp_s / ride.stop_s : 0.0;
  const double travel_s = continued_s + (ride.stop_s > 0.0 ? ramp_s - ramp_s * ramp_s / (2.0 * ride.stop_s) : 0.0);
  const bool ramping = silent_s > ride.continue_s;
  DriveSetpoint at = command;
  for (std::size_t i = 0; i < at.motor_angle_rad.size(); ++i) {
    at.motor_angle_rad[i] += command.motor_velocity_rad_s[i] * travel_s;
    at.motor_velocity_rad_s[i] = ramping ? command.motor_velocity_rad_s[i] * speed : command.motor_velocity_rad_s[i];
  }
  at.utime = command.utime + std::llround(std::max(silent_s, 0.0) * 1e6);
  return at;
}

}  // namespace edsp
