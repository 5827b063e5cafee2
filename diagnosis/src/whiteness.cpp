#include "edsp/diagnosis/whiteness.h"

#include <cmath>

namespace edsp::gap {

Whiteness TestWhiteness(const Design& d, const Eigen::VectorXd& residual, int lags) {
  Whiteness w;
  int series = 0, outside = 0, tested = 0;
  for (const ColumnRange& run : d.run_samples) {
    const int n = run.count;
    if (n < 4 * lags) continue;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> e(static_cast<std::size_t>(n));
      double mean = 0.0;
      for (int k = 0; k < n; ++k) mean += e[static_cast<std::size_t>(k)] = residual(3 * (run.begin + k) + axis);
      mean /= n;
      double c0 = 0.0;
      for (double& v : e) v -= mean, c0 += v * v;
      if (c0 <= 0.0) continue;
      const double band = 2.58 / std::sqrt(static_cast<double>(n));
      for (int lag = 1; lag <= lags; ++lag) {
        double c = 0.0;
        for (std::size_t k = 0; k + static_cast<std::size_t>(lag) < e.size(); ++k)
          c += e[k] * e[k + static_cast<std::size_t>(lag)];
        const double rho = c / c0;
        w.q += static_cast<double>(n) * (n + 2) * rho * rho / (n - lag);
        outside += std::abs(rho) > band;
        ++tested;
        if (lag == 1) w.lag1 += rho;
      }
      ++series;
    }
  }
  if (series == 0) return w;
  w.dof = lags * series;
  w.threshold = w.dof + 2.326 * std::sqrt(2.0 * w.dof);
  w.white = w.q <= w.threshold;
  w.lag1 /= series;
  w.outside_fraction = static_cast<double>(outside) / tested;
  return w;
}

}  // namespace edsp::gap
