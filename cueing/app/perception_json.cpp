#include "perception_json.h"

namespace edsp {

nlohmann::json ChannelsJson(const PerceptionScore& score) {
  nlohmann::json channels = nlohmann::json::object();
  for (int channel = 0; channel < kCueChannels; ++channel) {
    const ChannelScore& s = score.channels[static_cast<std::size_t>(channel)];
    channels[CueChannelName(channel)] = {{"rms_error", s.rms_error},
                                         {"correlation", s.correlation},
                                         {"delay_s", s.delay_s},
                                         {"in_thresholds", s.in_thresholds}};
  }
  return channels;
}

}  // namespace edsp
