// Manoeuvre files: the shapes they describe, and files that are wrong
// refused with the file, the line and the key.
#include "edsp/cueing/manoeuvre.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "edsp/node/build_paths.h"
#include "thrown_message.h"

namespace edsp {
namespace {

std::string ParseError(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseManoeuvre(text, "m.toml"); }, "(no error)");
}

TEST(Manoeuvre, APulseRisesHoldsAndFallsWithoutAStep) {
  const Manoeuvre m = ParseManoeuvre(R"(name = "p"
duration_s = 5.0
[[pulse]]
channel = "fy"
start_s = 1.0
rise_s = 0.5
hold_s = 1.0
fall_s = 0.5
amplitude = 2.0
)",
                                     "p.toml");
  EXPECT_EQ(m.At(0.9).specific_force_m_s2.y(), 0.0);
  EXPECT_NEAR(m.At(1.25).specific_force_m_s2.y(), 1.0, 1e-12);  // half way up
  EXPECT_EQ(m.At(2.0).specific_force_m_s2.y(), 2.0);
  EXPECT_NEAR(m.At(2.75).specific_force_m_s2.y(), 1.0, 1e-12);
  EXPECT_EQ(m.At(3.5).specific_force_m_s2.y(), 0.0);
  EXPECT_EQ(m.At(2.0).specific_force_m_s2.z(), kStandardGravity_m_s2);  // over gravity at rest
  // No step anywhere: successive samples at 1 kHz differ by at most the
  // ramp's peak slope (π A / 2 rise) times the period.
  const VehicleSeries series = SampleManoeuvre(m, 1e-3);
  EXPECT_EQ(series.samples.size(), 5001u);
  for (std::size_t k = 1; k < series.samples.size(); ++k) {
    ASSERT_LE(std::fabs(series.samples[k].specific_force_m_s2.y() - series.samples[k - 1].specific_force_m_s2.y()),
              kPi * 2.0 / (2.0 * 0.5) * 1e-3 * 1.001);
  }
}

TEST(Manoeuvre, ASineFadesInAndOut) {
  const Manoeuvre m = ParseManoeuvre(R"(name = "s"
duration_s = 10.0
[[sine]]
channel = "wz"
start_s = 2.0
duration_s = 6.0
fade_s = 1.0
amplitude = 0.3
frequency_hz = 0.25
)",
                                     "s.toml");
  EXPECT_EQ(m.At(1.0).angular_velocity_rad_s.z(), 0.0);
  EXPECT_NEAR(m.At(2.0 + 1.0).angular_velocity_rad_s.z(), 0.3 * std::sin(2.0 * kPi * 0.25), 1e-12);
  EXPECT_NEAR(m.At(8.0).angular_velocity_rad_s.z(), 0.0, 1e-12);
}

TEST(Manoeuvre, AWrongFileIsRefusedNamingTheLineAndKey) {
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[pulse]]\nchannel = \"ax\"\namplitude = 1\n")
                .find("m.toml:4: [[pulse]] #1 channel = \"ax\""),
            std::string::npos);
  EXPECT_NE(
      ParseError("name = \"x\"\nduration_s = 5\n[[pulse]]\nchannel = \"wx\"\nrise_s = 1\nfall_s = 1\namplitude = 20\n")
          .find("amplitude = 20 rad/s on wx"),
      std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[pulse]]\nchannel = \"fx\"\nstart_s = 3\nrise_s = 1\nhold_s = "
                       "1\nfall_s = 1\n")
                .find("ends at 6 s, after the manoeuvre's duration_s = 5"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[sine]]\nchannel = \"fx\"\nfreq = 1\n").find("unknown key"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = nan\n[[sine]]\nchannel = \"fx\"\n").find("duration_s"),
            std::string::npos);
  EXPECT_NE(ParseError("duration_s = 5\n[[sine]]\nchannel = \"fx\"\n").find("needs a name"), std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n").find("at least one"), std::string::npos);
  // A step, a name that is no file name, one too short to score, two
  // pulses adding up past 5 g, a negative time, a fade longer than half
  // its sine, a frequency beyond any motion base, a sine past the end.
  const std::string pulse = "[[pulse]]\nchannel = \"fx\"\nrise_s = 0.5\nhold_s = 1\nfall_s = 0.5\namplitude = 30\n";
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[pulse]]\nchannel = \"fx\"\nrise_s = 0\nfall_s = 1\n")
                .find("m.toml:5: [[pulse]] #1 rise_s = 0 must be > 0"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"../x\"\nduration_s = 5\n" + pulse).find("m.toml:1: name = \"../x\""),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 0.05\n" + pulse).find("duration_s = 0.05"), std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n" + pulse + pulse)
                .find("fx adds up to 49.12 at t = 0.360 s: beyond 49.03"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[sine]]\nchannel = \"fy\"\nstart_s = -1\n").find("start_s = -1"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[sine]]\nchannel = \"fy\"\nduration_s = 2\nfade_s = 1.5\n")
                .find("fade_s = 1.5 is more than half"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[sine]]\nchannel = \"fy\"\nfrequency_hz = 80\n")
                .find("frequency_hz = 80: beyond 50 Hz"),
            std::string::npos);
  EXPECT_NE(ParseError("name = \"x\"\nduration_s = 5\n[[sine]]\nchannel = \"fy\"\nstart_s = 4\nduration_s = 2\n")
                .find("ends at 6 s"),
            std::string::npos);
}

TEST(Manoeuvre, EveryShippedManoeuvreLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SourceDir() + "/config/manoeuvres")) {
    const Manoeuvre m = LoadManoeuvre(entry.path().string());
    EXPECT_FALSE(m.description.empty()) << entry.path();
    EXPECT_EQ(entry.path().stem().string(), m.name) << "a file is named after its manoeuvre";
    ++count;
  }
  EXPECT_GE(count, 7);
}

}  // namespace
}  // namespace edsp
