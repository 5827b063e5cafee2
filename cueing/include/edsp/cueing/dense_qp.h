#pragma once
// A small dense convex quadratic programme solved in real time: the
// model-predictive cueing's condensed problem (cueing/mpc_cueing.h), once
// per solve period.
//   minimise ½ xᵀ H x + gᵀ x   subject to   lower ≤ A x ≤ upper
// H (positive semidefinite) and A stay fixed for the solver's life (a
// time-invariant plant, fixed weights and horizon); g and the bounds change
// from solve to solve. Method: ADMM as OSQP runs it (Stellato et al. 2020,
// "OSQP: an operator splitting solver for quadratic programs", Math. Prog.
// Comp. 12): variables and rows equilibrated, over-relaxation, ρ adapted to the
// residuals' balance, warm starts from the last solution. The problems are
// tens of variables, so the one linear system is dense and refactored
// whenever ρ changes. Debian 12 packages neither OSQP nor qpOASES; this
// solver is checked against IPOPT (coinor-libipopt) on the same problems
// (tests/cueing/dense_qp_test.cpp).

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace edsp {

struct DenseQpSettings {
  double rho = 0.1;     // the step, adapted within [1e-6, 1e6]
  double sigma = 1e-6;  // keeps the system positive definite for a semidefinite H
  double alpha = 1.6;   // over-relaxation
  int max_iterations = 400;
  double eps_abs = 1e-6;  // on the residuals of the scaled problem (unit diagonal of H, unit rows of A)
  double eps_rel = 1e-5;
  int check_every = 5;  // iterations between convergence checks (and ρ updates)
  // Then the rows ADMM found active held as equalities and the KKT system
  // solved exactly (OSQP's polishing), kept when it is feasible and its
  // multipliers have the right signs: ADMM's slow last digits on an
  // ill-conditioned problem made exact.
  bool polish = true;
};

struct DenseQpResult {
  Eigen::VectorXd x;  // the solution
  Eigen::VectorXd y;  // the constraints' multipliers
  int iterations = 0;
  double primal_residual = 0.0;  // ‖A x − z‖∞: how far the solution is from the constraints
  double dual_residual = 0.0;    // ‖H x + g + Aᵀ y‖∞
  bool converged = false;        // within eps before max_iterations
  bool polished = false;         // the KKT solution on ADMM's active set was taken
};

class DenseQp {
 public:
  // Throws std::invalid_argument when H is not square, A does not have
  // H's columns, either is not finite, or a setting is absurd.
  DenseQp(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, DenseQpSettings settings = {});

  // Warm-started from the last solution. `lower` ≤ `upper` row by row
  // (−infinity, +infinity for a side without a bound); throws
  // std::invalid_argument naming the first row that is not.
  const DenseQpResult& Solve(const Eigen::VectorXd& g, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);
  // Forgets the last solution: the next Solve starts from zero.
  void Reset();
  const DenseQpResult& last() const { return result_; }

  int variables() const { return static_cast<int>(h_.rows()); }
  int constraints() const { return static_cast<int>(a_.rows()); }
  const Eigen::MatrixXd& hessian() const { return h_; }
  Eigen::MatrixXd constraint_matrix() const {
    return row_scale_.cwiseInverse().asDiagonal() * a_ * column_scale_.cwiseInverse().asDiagonal();
  }

 private:
  void Factor();
  // The exact solution on the active set ADMM found, if it holds.
  void Polish(const Eigen::VectorXd& g, const Eigen::VectorXd& l, const Eigen::VectorXd& u);

  Eigen::MatrixXd h_;             // as given
  Eigen::VectorXd column_scale_;  // x = column_scale_ · x̃: H's diagonal made 1
  Eigen::MatrixXd hs_;            // H in x̃
  Eigen::MatrixXd a_;             // A in x̃, rows scaled to unit ∞-norm
  Eigen::VectorXd row_scale_;     // a_ = row_scale_ · A · column_scale_
  DenseQpSettings settings_;
  double rho_;
  Eigen::LLT<Eigen::MatrixXd> kkt_;  // H + σI + ρ AᵀA
  Eigen::VectorXd x_, z_, y_;        // the iterates, in x̃ and the scaled rows
  DenseQpResult result_;
};

}  // namespace edsp
