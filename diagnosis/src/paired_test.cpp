#include "edsp/diagnosis/paired_test.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

#include <boost/math/distributions/students_t.hpp>

namespace edsp::gap {

namespace {

// Student's t on the mean gain, one-sided.
bool MeanGainIsSignificant(const std::vector<double>& gain, double alpha) {
  const std::size_t n = gain.size();
  const double mean = std::accumulate(gain.begin(), gain.end(), 0.0) / static_cast<double>(n);
  if (n < 2 || mean <= 0.0) return mean > 0.0;
  double var = 0.0;
  for (double g : gain) var += (g - mean) * (g - mean);
  var /= static_cast<double>(n - 1);
  if (var <= 0.0) return true;
  const double t = mean / std::sqrt(var / static_cast<double>(n));
  const boost::math::students_t dist(static_cast<double>(n - 1));
  return t > boost::math::quantile(boost::math::complement(dist, alpha));
}

}  // namespace

double SignedRankPValue(const std::vector<double>& gain) {
  std::vector<double> nonzero;
  for (double g : gain) {
    if (g != 0.0) nonzero.push_back(g);
  }
  const int n = static_cast<int>(nonzero.size());
  if (n == 0) return 1.0;
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return std::abs(nonzero[static_cast<std::size_t>(a)]) < std::abs(nonzero[static_cast<std::size_t>(b)]);
  });
  int w_plus = 0;
  for (int r = 0; r < n; ++r)
    w_plus += nonzero[static_cast<std::size_t>(order[static_cast<std::size_t>(r)])] > 0.0 ? r + 1 : 0;
  // ways[w]: subsets of the ranks 1..n summing to w.
  const int total = n * (n + 1) / 2;
  std::vector<double> ways(static_cast<std::size_t>(total + 1), 0.0);
  ways[0] = 1.0;
  for (int r = 1; r <= n; ++r) {
    for (int w = total; w >= r; --w) ways[static_cast<std::size_t>(w)] += ways[static_cast<std::size_t>(w - r)];
  }
  double at_least = 0.0;
  for (int w = w_plus; w <= total; ++w) at_least += ways[static_cast<std::size_t>(w)];
  return at_least / std::pow(2.0, n);
}

bool PairedGainIsSignificant(const std::vector<double>& gain, double alpha) {
  if (gain.empty()) return false;
  if (MeanGainIsSignificant(gain, alpha)) return true;
  return static_cast<int>(gain.size()) >= kMinRunsForSignedRank && SignedRankPValue(gain) <= kSignedRankLevel;
}

}  // namespace edsp::gap
