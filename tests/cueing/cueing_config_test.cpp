// The cueing config: every absurd value refused at its own line and key.
#include "edsp/cueing/cueing_config.h"

#include <gtest/gtest.h>

#include "edsp/node/build_paths.h"
#include "thrown_message.h"

namespace edsp {
namespace {

std::string Error(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseCueingConfig(text, "c.toml"); }, "(no error)");
}

TEST(CueingConfig, TheShippedFileLoadsWithItsDocumentedValues) {
  const CueingConfig c = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  EXPECT_EQ(c.rate_hz, 1000.0);
  EXPECT_EQ(c.input.timeout_s, 0.1);
  EXPECT_EQ(c.washout.tilt_accel_max_rad_s2, 0.5);
  EXPECT_EQ(c.perception.otolith.tau_a_s, 13.2);
}

TEST(CueingConfig, EveryAbsurdValueIsNamedAtItsLine) {
  EXPECT_EQ(Error("[washout]\ntilt_damping = 1\nspecific_force_scale = 1.5\n"),
            "c.toml:3: [washout] specific_force_scale = 1.5 must be in (0, 1]");
  EXPECT_EQ(Error("[washout]\n\ntilt_max_rad = 1.6\n"), "c.toml:3: [washout] tilt_max_rad = 1.6 must be under π/2");
  EXPECT_EQ(Error("[input]\ntimeout_s = 2\n"),
            "c.toml:2: [input] timeout_s = 2: a rider would ride a second on a dead input (at most 1 s)");
  EXPECT_EQ(Error("[cueing]\nrate_hz = 20\n"), "c.toml:2: [cueing] rate_hz = 20 is outside 50..10000 Hz");
  EXPECT_NE(Error("[washout]\ntilt_rate = 0.1\n").find("unknown key [washout] tilt_rate"), std::string::npos);
  EXPECT_NE(Error("[perception]\ncanal_threshold_rad_s = [0.05, 0, 0.05]\n").find("every element must be > 0"),
            std::string::npos);
}

}  // namespace
}  // namespace edsp
