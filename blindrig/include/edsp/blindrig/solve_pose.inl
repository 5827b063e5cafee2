#pragma once
// Newton's method for PoseSolver and SolvePose (blind_kinematics.h).

#include <limits>
#include <stdexcept>

namespace edsp::blind {

template <typename Residual>
void PoseSolver::Factor(const Residual& residual, const Vec6& q) {
  constexpr double kStep = 1e-7;  // central differences: error ~ step², rounding ~ 1e-16/step
  Eigen::Matrix<double, 6, 6> J;
  for (int k = 0; k < 6; ++k) {
    Vec6 plus = q, minus = q;
    plus(k) += kStep;
    minus(k) -= kStep;
    J.col(k) = (residual(plus) - residual(minus)) / (2.0 * kStep);
  }
  jacobian_.compute(J);
  factored_ = true;
}

template <typename Residual>
Vec6 PoseSolver::Solve(const Residual& residual, Vec6 q, double tolerance) {
  constexpr double kContraction = 0.01;  // what a kept Jacobian must still do each step (fewest residuals on a 1 kHz path)
  double previous = std::numeric_limits<double>::infinity();  // the residual before the last step
  Vec6 r = residual(q);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double size = r.cwiseAbs().maxCoeff();
    if (size < tolerance) return q;
    if (!factored_ || !(size < kContraction * previous)) Factor(residual, q);
    previous = size;
    q -= jacobian_.solve(r);
    r = residual(q);
  }
  throw std::runtime_error("blind rig: forward kinematics did not converge");
}

template <typename Residual>
Vec6 SolvePose(const Residual& residual, Vec6 guess, double tolerance) {
  PoseSolver solver;
  return solver.Solve(residual, guess, tolerance);
}

}  // namespace edsp::blind
