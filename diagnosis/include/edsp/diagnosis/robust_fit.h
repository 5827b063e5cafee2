#pragma once
// The final fit of the selected effects with Ceres: the tracker frame's
// rotation exact (not linearised), a Huber loss so tracker dropouts and
// spikes do not pull the parameters, and the parameters' covariance (dense
// SVD: directions the data cannot see are dropped, not inverted).

#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct RobustFit {
  Eigen::VectorXd theta;     // the columns' parameters, in the order given
  Eigen::VectorXd sigma;     // their 1-σ uncertainties
  Eigen::VectorXd frame;     // δω (3), δt (3) around the design's (R0, t0)
  Eigen::VectorXd residual;  // 3 per sample, at the solution
  double huber_m = 0.0;
  int iterations = 0;
  bool converged = false;
  bool covariance_ok = false;
};

// `columns`: design columns of the effects (frame columns excluded);
// `start`: their starting values (the linear fit's); `prior_weight`: the
// linear fit's ridge per column (σ²/σ_prior²; empty for none), so both fits
// pin the directions the data cannot see the same way.
RobustFit FitRobust(const Design& design, const std::vector<int>& columns, const Eigen::VectorXd& start, double huber_m,
                    const Eigen::VectorXd& prior_weight = {});

}  // namespace edsp::gap
