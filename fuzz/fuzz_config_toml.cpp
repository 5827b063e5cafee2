// libFuzzer: the platform config loader (TOML text → PlatformConfig, every
// check). Bad input must end in std::runtime_error naming what is wrong,
// never in a crash, a hang or undefined behaviour.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_effects.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 16)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const edsp::PlatformConfig config = edsp::ParseConfig(text, "fuzz.toml");
    edsp::ValidateConfig(config, "fuzz.toml");
  } catch (const std::exception&) {
  }
  try {
    (void)edsp::ParseRigEffects(text, "fuzz.toml");
  } catch (const std::exception&) {
  }
  return 0;
}
