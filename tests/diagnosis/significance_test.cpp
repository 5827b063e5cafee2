// The paired test (paired_test.h) that keeps a gain one held-out run
// carries from making an effect `identified`: Student's t against its
// table, Wilcoxon's signed rank against its table and a brute-force count
// over every sign pattern; and the tie of two explanations it decides with
// the gains' ratio (effect_sets.h's Tied).
#include <vector>

#include <gtest/gtest.h>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/effect_sets.h"
#include "edsp/diagnosis/paired_test.h"

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

// n = 6: P(W⁺ ≥ 19) = 3/64 (the negative ranks sum to at most 2: {}, {1},
// {2}); P(W⁺ ≥ 18) = 5/64; all six positive: 1/64.
TEST(SignedRank, SixRunsAgainstTheTable) {
  EXPECT_DOUBLE_EQ(SignedRankPValue({-2.0, 1.0, 3.0, 4.0, 5.0, 6.0}), 3.0 / 64.0);
  EXPECT_DOUBLE_EQ(SignedRankPValue({-3.0, 1.0, 2.0, 4.0, 5.0, 6.0}), 5.0 / 64.0);
  EXPECT_DOUBLE_EQ(SignedRankPValue({0.5, 1.0, 2.0, 4.0, 5.0, 6.0}), 1.0 / 64.0);
  EXPECT_DOUBLE_EQ(SignedRankPValue({0.0, 0.0}), 1.0);
}

// Against a count over all 2⁸ sign patterns of the ranks.
TEST(SignedRank, EightRunsAgainstEverySignPattern) {
  const std::vector<double> gain = {0.3, -0.05, 0.8, 0.12, -0.4, 0.6, 0.9, 0.2};  // ranks 4, 1, 7, 2, 5, 6, 8, 3
  const int w_plus = 4 + 7 + 2 + 6 + 8 + 3;
  int at_least = 0;
  for (int signs = 0; signs < 256; ++signs) {
    int w = 0;
    for (int r = 1; r <= 8; ++r) w += (signs >> (r - 1)) & 1 ? r : 0;
    at_least += w >= w_plus;
  }
  EXPECT_DOUBLE_EQ(SignedRankPValue(gain), at_least / 256.0);  // 14/256
}

// Every run gains, by very different amounts (an effect the rotations
// excite far more than the lifts): the mean's t is 1.09 on 7 degrees of
// freedom, but the signs are not a coin toss (p = 1/256).
TEST(PairedGain, AGainEveryRunShowsIsSignificantHoweverUnequal) {
  EXPECT_TRUE(PairedGainIsSignificant({10.0, 0.1, 0.1, 0.2, 0.1, 0.15, 0.1, 0.1}, 0.05));
  // Two of the eight lose (W⁻ = 3, p = 5/256 = 0.02): the ranks' strict
  // level is not met, and the t-test fails as before.
  EXPECT_FALSE(PairedGainIsSignificant({10.0, 0.2, 0.2, 0.2, 0.2, 0.2, -0.1, -0.12}, 0.05));
  // Six folds cannot reach the ranks' 1% (1/64 at best): the t-test decides (t = 1.08).
  EXPECT_FALSE(PairedGainIsSignificant({10.0, 0.1, 0.1, 0.2, 0.1, 0.15}, 0.05));
}

// Two explanations are tied only where both halves say so: the challenger
// takes up most of the incumbent's gain, and the runs do not favour the
// incumbent. Each half alone breaks the tie.
TEST(Tie, TheGainsAndTheRunsMustBothTie) {
  const DiagnoseOptions o;
  const double incumbent = 0.20, most = 0.8 * incumbent, less = 0.5 * incumbent;
  ASSERT_GE(most, o.ambiguity_ratio * incumbent);
  ASSERT_LT(less, o.ambiguity_ratio * incumbent);
  const std::vector<double> every_run_favours = {0.05, 0.04, 0.06, 0.05, 0.03, 0.05, 0.04, 0.06};
  const std::vector<double> runs_split = {0.05, -0.04, 0.06, -0.05, 0.03, -0.05, 0.04, -0.06};
  ASSERT_TRUE(PairedGainIsSignificant(every_run_favours, o.significance));
  ASSERT_FALSE(PairedGainIsSignificant(runs_split, o.significance));
  EXPECT_TRUE(Tied(
      most, incumbent, [&] { return runs_split; }, o));
  EXPECT_FALSE(Tied(
      most, incumbent, [&] { return every_run_favours; }, o));  // the runs tell them apart
  EXPECT_FALSE(Tied(
      less, incumbent, [&] { return runs_split; }, o));  // the gains do
  // A challenger that gains less than an effect must is no alternative,
  // however small the incumbent's own gain.
  EXPECT_FALSE(Tied(
      0.8 * o.min_cv_gain, o.min_cv_gain, [&] { return runs_split; }, o));
}

// The run-by-run half fits every fold: it is asked for only when the gains tie.
TEST(Tie, TheRunsAreAskedOnlyWhenTheGainsTie) {
  const DiagnoseOptions o;
  int asked = 0;
  const auto runs = [&] {
    ++asked;
    return std::vector<double>{0.05, -0.04, 0.06, -0.05};
  };
  EXPECT_FALSE(Tied(0.01, 0.20, runs, o));
  EXPECT_EQ(asked, 0);
  EXPECT_TRUE(Tied(0.19, 0.20, runs, o));
  EXPECT_EQ(asked, 1);
}

}  // namespace
}  // namespace edsp::gap
