#pragma once
// Is what is left white noise? The residual autocorrelation test of MATLAB's
// `resid`, pooled as a Ljung–Box statistic over runs and axes.

#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct Whiteness {
  bool white = true;
  double q = 0.0;                 // Ljung–Box statistic, pooled
  int dof = 0;                    // lags × series
  double threshold = 0.0;         // 99% quantile of χ²(dof) (normal approximation)
  double lag1 = 0.0;              // mean lag-1 autocorrelation over the series
  double outside_fraction = 0.0;  // of lags outside ±2.58/√N (resid's 99% band)
};

// `residual` holds 3 values per sample of `design` (its run blocks).
Whiteness TestWhiteness(const Design& design, const Eigen::VectorXd& residual, int lags = 25);

}  // namespace edsp::gap
