#pragma once
// What the benchmarks share to draw rigs and summarise their scores.

#include <algorithm>
#include <random>
#include <vector>

namespace edsp::gap {

using Rng = std::mt19937_64;

inline double Uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

// The median of `v` (0 for none).
inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace edsp::gap
