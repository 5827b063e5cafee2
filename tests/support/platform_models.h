#pragma once
// The paper's platform as the tests build it: from edsp's preset, or from the
// shipped config file as a user's config would be read.

#include <string>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/node/build_paths.h"

namespace edsp::test_support {

inline const std::string kShippedConfig = SourcePath("config/huang2021.toml");

inline PlatformModel Huang2021Model() { return PlatformModel(Huang2021Config()); }
inline PlatformModel ShippedConfigModel() { return PlatformModel(LoadConfigFile(kShippedConfig)); }

}  // namespace edsp::test_support
