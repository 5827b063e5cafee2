// The manoeuvres' variants the bench scores beside the shipped files: each
// is its manoeuvre with every amplitude scaled by one factor and every hold
// shortened by another, within the variation; a seed draws the same ones
// again, another seed others; and each still ends inside its file's duration.
#include "edsp/cueing/manoeuvre_variants.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

Manoeuvre Shipped(const std::string& name) {
  return LoadManoeuvre(SourceDir() + "/config/manoeuvres/" + name + ".toml");
}

TEST(ManoeuvreVariants, EachScalesEveryAmplitudeByOneFactorAndShortensEveryHold) {
  for (const char* name : {"braking", "take_off_roll", "turbulence", "coordinated_turn"}) {
    const Manoeuvre m = Shipped(name);
    const auto variants = ManoeuvreVariants(m, 5, 2026);
    ASSERT_EQ(variants.size(), 5U);
    for (std::size_t k = 0; k < variants.size(); ++k) {
      const Manoeuvre& v = variants[k];
      EXPECT_EQ(v.name, std::string(name) + "_v" + std::to_string(k));
      ASSERT_EQ(v.pulses.size(), m.pulses.size());
      ASSERT_EQ(v.sines.size(), m.sines.size());
      double factor = 0.0;
      const auto same_factor = [&](double scaled, double original) {
        if (original == 0.0) return;
        if (factor == 0.0) factor = scaled / original;
        EXPECT_NEAR(scaled / original, factor, 1e-12) << v.name;
      };
      for (std::size_t p = 0; p < m.pulses.size(); ++p) {
        same_factor(v.pulses[p].amplitude, m.pulses[p].amplitude);
        EXPECT_LE(v.pulses[p].hold_s, m.pulses[p].hold_s) << v.name;
        EXPECT_GE(v.pulses[p].hold_s, 0.6 * m.pulses[p].hold_s - 1e-12) << v.name;
        EXPECT_LE(v.pulses[p].start_s + v.pulses[p].rise_s + v.pulses[p].hold_s + v.pulses[p].fall_s,
                  v.duration_s + 1e-9);
      }
      for (std::size_t s = 0; s < m.sines.size(); ++s) same_factor(v.sines[s].amplitude, m.sines[s].amplitude);
      EXPECT_GE(factor, 0.6) << v.name;
      EXPECT_LE(factor, 1.4) << v.name;
    }
  }
}

TEST(ManoeuvreVariants, ASeedDrawsTheSameVariantsAgainAndAnotherSeedOthers) {
  const Manoeuvre m = Shipped("braking");
  const auto a = ManoeuvreVariants(m, 3, 2026), b = ManoeuvreVariants(m, 3, 2026), c = ManoeuvreVariants(m, 3, 7);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(a[k].pulses[0].amplitude, b[k].pulses[0].amplitude);
    EXPECT_NE(a[k].pulses[0].amplitude, c[k].pulses[0].amplitude);
  }
  EXPECT_NE(a[0].pulses[0].amplitude, a[1].pulses[0].amplitude) << "the variants differ from each other";
}

TEST(ManoeuvreVariants, AnAbsurdVariationIsNamed) {
  ManoeuvreVariation v;
  v.amplitude_min = 1.5;
  v.amplitude_max = 1.2;
  try {
    ManoeuvreVariants(Shipped("braking"), 1, 1, v);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("amplitude"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp
