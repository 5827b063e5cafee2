#pragma once
// What a vehicle model sends a motion system: the specific force and the
// angular velocity at the rider's head, in the head frame {H}: x forward,
// y left, z up (right-handed, as the platform's {M} at its neutral pose).
// Specific force f = a − g: at rest on level ground f = (0, 0, +g).

#include <vector>

#include "edsp/kinematics/types.h"

namespace edsp {

inline constexpr double kStandardGravity_m_s2 = 9.80665;

struct VehicleSample {
  double t_s = 0.0;
  Vector3 specific_force_m_s2 = Vector3(0.0, 0.0, kStandardGravity_m_s2);
  Vector3 angular_velocity_rad_s = Vector3::Zero();
};

// Samples at one fixed period, oldest first.
struct VehicleSeries {
  double period_s = 1e-3;
  std::vector<VehicleSample> samples;
};

// Six channels in one order wherever per-axis figures are listed:
// fx fy fz (m/s²) wx wy wz (rad/s).
inline constexpr int kCueChannels = 6;
const char* CueChannelName(int channel);
// −1 when `name` is none of them.
int CueChannelIndex(const char* name);
double ChannelValue(const VehicleSample& sample, int channel);

}  // namespace edsp
