#pragma once
// The one thing the second rig takes from edsp: the numbers of a platform
// config (joints, axes, home height, lead, s, point A), read by edsp's config
// loader. Everything computed from them is the blind rig's own.

#include "edsp/blindrig/blind_rig.h"
#include "edsp/kinematics/config.h"

namespace edsp::blind {

BlindRigSetup SetupFromConfig(const PlatformConfig& config);

}  // namespace edsp::blind
