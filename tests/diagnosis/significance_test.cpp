// The paired test that keeps a gain one held-out run carries from making an
// effect `identified`, checked against Student's t table.
#include <gtest/gtest.h>

#include "edsp/diagnosis/diagnose.h"

namespace edsp::gap {
namespace {

// Gains 1, 2, 3: mean 2, s = 1, t = 2·√3 = 3.464 on 2 degrees of freedom;
// the table's one-sided critical values are 2.920 (5%) and 6.965 (1%).
TEST(PairedGain, ThreeRunsAgainstTheTable) {
  EXPECT_TRUE(PairedGainIsSignificant({1.0, 2.0, 3.0}, 0.05));
  EXPECT_FALSE(PairedGainIsSignificant({1.0, 2.0, 3.0}, 0.01));
  // Same mean, more scatter (s = 3, t = 1.155): not significant.
  EXPECT_FALSE(PairedGainIsSignificant({-1.0, 2.0, 5.0}, 0.05));
}

// One run carries the whole pooled gain: on 8 runs, t = 1 whatever its size.
TEST(PairedGain, AGainOneRunCarriesIsNotSignificant) {
  EXPECT_FALSE(PairedGainIsSignificant({100.0, 0, 0, 0, 0, 0, 0, 0}, 0.05));
  EXPECT_TRUE(PairedGainIsSignificant({1.1, 0.9, 1.0, 1.2, 0.8, 1.0, 1.05, 0.95}, 0.05));
}

TEST(PairedGain, NoGainOrALossIsNeverSignificant) {
  EXPECT_FALSE(PairedGainIsSignificant({}, 0.05));
  EXPECT_FALSE(PairedGainIsSignificant({0.0, 0.0, 0.0}, 0.05));
  EXPECT_FALSE(PairedGainIsSignificant({-1.0, -1.0, -1.0}, 0.05));
  EXPECT_TRUE(PairedGainIsSignificant({2.0, 2.0, 2.0}, 0.05));  // no scatter at all
}

}  // namespace
}  // namespace edsp::gap
