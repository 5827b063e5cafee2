#pragma once
// Newton's method for SolvePose (blind_kinematics.h).

#include <stdexcept>

#include <Eigen/LU>

namespace edsp::blind {

template <typename Residual>
Vec6 SolvePose(const Residual& residual, Vec6 q, double tolerance) {
  constexpr double kStep = 1e-7;  // central differences: error ~ step², rounding ~ 1e-16/step
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Vec6 r = residual(q);
    if (r.cwiseAbs().maxCoeff() < tolerance) return q;
    Eigen::Matrix<double, 6, 6> J;
    for (int k = 0; k < 6; ++k) {
      Vec6 plus = q, minus = q;
      plus(k) += kStep;
      minus(k) -= kStep;
      J.col(k) = (residual(plus) - residual(minus)) / (2.0 * kStep);
    }
    q -= J.partialPivLu().solve(r);
  }
  throw std::runtime_error("blind rig: forward kinematics did not converge");
}

}  // namespace edsp::blind
