#include "edsp/cueing/dense_qp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/LU>

#include <fmt/format.h>

namespace edsp {
namespace {

constexpr double kRhoMin = 1e-6, kRhoMax = 1e6;
constexpr double kRhoChange = 5.0;  // refactor only for a change of more than this factor
constexpr double kTiny = 1e-30;

double InfNorm(const Eigen::VectorXd& v) { return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff(); }

}  // namespace

DenseQp::DenseQp(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, DenseQpSettings settings)
    : h_(H), settings_(settings), rho_(settings.rho) {
  if (H.rows() != H.cols()) throw std::invalid_argument(fmt::format("QP: H is {}x{}, not square", H.rows(), H.cols()));
  if (A.cols() != H.cols()) {
    throw std::invalid_argument(fmt::format("QP: A has {} columns, H {}", A.cols(), H.cols()));
  }
  if (!H.allFinite() || !A.allFinite()) throw std::invalid_argument("QP: H or A has a value that is not finite");
  if (settings.check_every < 1 || settings.max_iterations < 1 || !(settings.rho > 0.0) || !(settings.sigma > 0.0) ||
      !(settings.alpha > 0.0 && settings.alpha < 2.0)) {
    throw std::invalid_argument(fmt::format(
        "QP settings: check_every {} and max_iterations {} must be ≥ 1, rho {} and sigma {} > 0, alpha {} in (0, 2)",
        settings.check_every, settings.max_iterations, settings.rho, settings.sigma, settings.alpha));
  }
  // Variables scaled to a unit diagonal of H, then rows of A to unit ∞-norm.
  column_scale_ = Eigen::VectorXd::Ones(H.rows());
  for (Eigen::Index j = 0; j < H.rows(); ++j) {
    if (H(j, j) > kTiny) column_scale_(j) = 1.0 / std::sqrt(H(j, j));
  }
  hs_ = column_scale_.asDiagonal() * H * column_scale_.asDiagonal();
  const Eigen::MatrixXd scaled_columns = A * column_scale_.asDiagonal();
  row_scale_ = Eigen::VectorXd::Ones(A.rows());
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    const double norm = scaled_columns.row(i).cwiseAbs().maxCoeff();
    if (norm > kTiny) row_scale_(i) = 1.0 / norm;
  }
  a_ = row_scale_.asDiagonal() * scaled_columns;
  Factor();
  Reset();
}

void DenseQp::Factor() {
  const Eigen::Index n = h_.rows();
  kkt_.compute(hs_ + settings_.sigma * Eigen::MatrixXd::Identity(n, n) + rho_ * a_.transpose() * a_);
}

void DenseQp::Reset() {
  x_ = Eigen::VectorXd::Zero(h_.rows());
  z_ = Eigen::VectorXd::Zero(a_.rows());
  y_ = Eigen::VectorXd::Zero(a_.rows());
}

const DenseQpResult& DenseQp::Solve(const Eigen::VectorXd& g, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper) {
  if (g.size() != h_.rows() || lower.size() != a_.rows() || upper.size() != a_.rows()) {
    throw std::invalid_argument(fmt::format("QP: g has {} entries (want {}), bounds {} and {} (want {})", g.size(),
                                            h_.rows(), lower.size(), upper.size(), a_.rows()));
  }
  if (!g.allFinite()) throw std::invalid_argument("QP: g has a value that is not finite");
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    if (!(lower(i) <= upper(i)) || lower(i) == std::numeric_limits<double>::infinity() ||
        upper(i) == -std::numeric_limits<double>::infinity()) {
      throw std::invalid_argument(
          fmt::format("QP: row {}: lower bound {} is not at most the upper {}", i, lower(i), upper(i)));
    }
  }
  const Eigen::VectorXd l = row_scale_.cwiseProduct(lower), u = row_scale_.cwiseProduct(upper);
  const Eigen::VectorXd gs = column_scale_.cwiseProduct(g);
  const double alpha = settings_.alpha;
  z_ = (a_ * x_).cwiseMax(l).cwiseMin(u);
  result_.converged = false;
  int iteration = 0;
  while (iteration < settings_.max_iterations) {
    ++iteration;
    const Eigen::VectorXd x_tilde = kkt_.solve(settings_.sigma * x_ - gs + a_.transpose() * (rho_ * z_ - y_));
    const Eigen::VectorXd z_relaxed = alpha * (a_ * x_tilde) + (1.0 - alpha) * z_;
    x_ = alpha * x_tilde + (1.0 - alpha) * x_;
    const Eigen::VectorXd z_next = (z_relaxed + y_ / rho_).cwiseMax(l).cwiseMin(u);
    y_ += rho_ * (z_relaxed - z_next);
    z_ = z_next;
    if (iteration % settings_.check_every != 0 && iteration != settings_.max_iterations) continue;
    const Eigen::VectorXd ax = a_ * x_, hx = hs_ * x_, aty = a_.transpose() * y_;
    const double primal = InfNorm(ax - z_), dual = InfNorm(hx + gs + aty);
    const double primal_scale = std::max(InfNorm(ax), InfNorm(z_));
    const double dual_scale = std::max({InfNorm(hx), InfNorm(aty), InfNorm(gs)});
    if (primal <= settings_.eps_abs + settings_.eps_rel * primal_scale &&
        dual <= settings_.eps_abs + settings_.eps_rel * dual_scale) {
      result_.converged = true;
      break;
    }
    const double ratio =
        std::sqrt((primal / std::max(primal_scale, kTiny)) / std::max(dual / std::max(dual_scale, kTiny), kTiny));
    const double rho = std::clamp(rho_ * ratio, kRhoMin, kRhoMax);
    if (rho > kRhoChange * rho_ || rho < rho_ / kRhoChange) {
      rho_ = rho;
      Factor();
    }
  }
  result_.iterations = iteration;
  result_.polished = false;
  if (settings_.polish) Polish(gs, l, u);
  result_.x = column_scale_.cwiseProduct(x_);
  result_.y = row_scale_.cwiseProduct(y_);
  result_.primal_residual = InfNorm((a_ * x_ - z_).cwiseQuotient(row_scale_));
  result_.dual_residual = InfNorm(h_ * result_.x + g + (a_.transpose() * y_).cwiseQuotient(column_scale_));
  return result_;
}

void DenseQp::Polish(const Eigen::VectorXd& g, const Eigen::VectorXd& l, const Eigen::VectorXd& u) {
  // Active rows as OSQP guesses them: z against a bound its multiplier presses on.
  std::vector<Eigen::Index> lower, upper;
  for (Eigen::Index i = 0; i < a_.rows(); ++i) {
    if (z_(i) - l(i) < -y_(i)) {
      lower.push_back(i);
    } else if (u(i) - z_(i) < y_(i)) {
      upper.push_back(i);
    }
  }
  const Eigen::Index n = h_.rows(), active = static_cast<Eigen::Index>(lower.size() + upper.size());
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + active, n + active);
  Eigen::VectorXd rhs(n + active);
  kkt.topLeftCorner(n, n) = hs_;
  rhs.head(n) = -g;
  Eigen::Index row = n;
  for (const auto* side : {&lower, &upper}) {
    for (Eigen::Index i : *side) {
      kkt.block(row, 0, 1, n) = a_.row(i);
      kkt.block(0, row, n, 1) = a_.row(i).transpose();
      rhs(row++) = side == &lower ? l(i) : u(i);
    }
  }
  const Eigen::VectorXd solution = kkt.fullPivLu().solve(rhs);
  if (!solution.allFinite()) return;
  // A singular system (active rows that depend on each other) gives some
  // vector that need not solve it: taken only if it does.
  if ((kkt * solution - rhs).cwiseAbs().maxCoeff() > settings_.eps_abs + settings_.eps_rel * InfNorm(rhs)) return;
  const Eigen::VectorXd x = solution.head(n), multipliers = solution.tail(active);
  const Eigen::VectorXd ax = a_ * x;
  const double tolerance = settings_.eps_abs + settings_.eps_rel * std::max(1.0, InfNorm(ax));
  for (Eigen::Index i = 0; i < ax.size(); ++i) {
    if (ax(i) < l(i) - tolerance || ax(i) > u(i) + tolerance) return;  // leaves a bound: not the active set
  }
  // Pressing outward only: a row held at its lower bound pulls with y ≤ 0, at its upper with y ≥ 0.
  for (std::size_t k = 0; k < lower.size(); ++k) {
    if (multipliers(static_cast<Eigen::Index>(k)) > tolerance) return;
  }
  for (std::size_t k = 0; k < upper.size(); ++k) {
    if (multipliers(static_cast<Eigen::Index>(lower.size() + k)) < -tolerance) return;
  }
  Eigen::VectorXd y = Eigen::VectorXd::Zero(a_.rows());
  Eigen::Index next = 0;
  for (Eigen::Index i : lower) y(i) = multipliers(next++);
  for (Eigen::Index i : upper) y(i) = multipliers(next++);
  // No worse than ADMM's own answer in the dual residual (OSQP's rule).
  const double dual = InfNorm(hs_ * x + g + a_.transpose() * y);
  if (dual > std::max(InfNorm(hs_ * x_ + g + a_.transpose() * y_), settings_.eps_abs)) return;
  x_ = x;
  z_ = ax.cwiseMax(l).cwiseMin(u);
  y_ = y;
  result_.polished = true;
  result_.converged = true;  // the KKT conditions hold exactly on the active set
}

}  // namespace edsp
