#include "edsp/cueing/vehicle_motion.h"

#include <cstring>

namespace edsp {
namespace {
constexpr const char* kChannelNames[kCueChannels] = {"fx", "fy", "fz", "wx", "wy", "wz"};
}  // namespace

const char* CueChannelName(int channel) {
  return channel >= 0 && channel < kCueChannels ? kChannelNames[channel] : "?";
}

int CueChannelIndex(const char* name) {
  for (int channel = 0; channel < kCueChannels; ++channel) {
    if (std::strcmp(name, kChannelNames[channel]) == 0) return channel;
  }
  return -1;
}

double ChannelValue(const VehicleSample& sample, int channel) {
  return channel < 3 ? sample.specific_force_m_s2(channel) : sample.angular_velocity_rad_s(channel - 3);
}

}  // namespace edsp
