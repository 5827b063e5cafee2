#pragma once
// Newton's method for PoseSolver and SolvePose (blind_kinematics.h).

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
  bool fresh = !factored_;
  if (fresh) Factor(residual, q);
  Vec6 r = residual(q);
  double size = r.cwiseAbs().maxCoeff();
  for (int iteration = 0; iteration < 50; ++iteration) {
    if (size < tolerance) return q;
    const Vec6 next = q - jacobian_.solve(r);
    const Vec6 r_next = residual(next);
    const double next_size = r_next.cwiseAbs().maxCoeff();
    // A fresh Jacobian's step is Newton's, taken as it comes; a kept one's
    // only if it contracts (NaN does not), else a fresh one where q is.
    if (fresh || next_size < kContraction * size) {
      q = next;
      r = r_next;
      size = next_size;
      fresh = false;
    } else {
      Factor(residual, q);
      fresh = true;
    }
  }
  factored_ = false;  // whatever it was, the next solve starts afresh
  throw std::runtime_error("blind rig: forward kinematics did not converge");
}

template <typename Residual>
Vec6 SolvePose(const Residual& residual, Vec6 guess, double tolerance) {
  PoseSolver solver;
  return solver.Solve(residual, guess, tolerance);
}

}  // namespace edsp::blind
