#pragma once
// A perception score's six channels as JSON, as every edsp-cueing command
// prints them: {"fx": {"rms_error", "correlation", "delay_s", "in_thresholds"}, …}.

#include <nlohmann/json.hpp>

#include "edsp/cueing/perception_score.h"

namespace edsp {

nlohmann::json ChannelsJson(const PerceptionScore& score);

}  // namespace edsp
