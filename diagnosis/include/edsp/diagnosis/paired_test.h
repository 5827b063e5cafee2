#pragma once
// The paired test over held-out runs that every `identified`, every tie
// and every check beyond the vocabulary asks: does a gain hold run by run,
// not only pooled? Each value is one held-out fold's gain (a log ratio of
// its squared errors, effect_sets.h's LogGains).

#include <vector>

namespace edsp::gap {

// Whether `gain` (one value per held-out fold) is above zero: Student's t
// on the mean, one-sided at level `alpha` (one fold: significant when
// positive), or — from kMinRunsForSignedRank folds on — Wilcoxon's
// signed-rank test at kSignedRankLevel. Runs excite an effect unequally (a
// sway rings in the rotations, hardly in the lifts): the t-test fails a
// gain every run shows when its size scatters, the ranks do not. Their
// level is strict (seven folds: all gain; eight: all, or all but the
// smallest change), so that they add only gains nearly every run shows; a
// gain one run carries fails both (the other runs' signs are a coin toss).
// Fewer than seven folds cannot reach 1% by ranks (2⁻⁶ = 1.6%).
inline constexpr double kSignedRankLevel = 0.01;
inline constexpr int kMinRunsForSignedRank = 7;
bool PairedGainIsSignificant(const std::vector<double>& gain, double alpha);
// Wilcoxon's signed-rank test, one-sided, exact: the chance that the ranks
// of |gain| the positive gains hold sum to W⁺ or more when each sign is a
// coin toss. Zero gains are dropped; ties are not averaged (the gains are
// continuous). 1 for no non-zero gain.
double SignedRankPValue(const std::vector<double>& gain);

}  // namespace edsp::gap
