#include "edsp/diagnosis/linear_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <fmt/format.h>

namespace edsp::gap {

std::vector<Fold> MakeFolds(const Design& d) {
  std::vector<Fold> folds;
  const int runs = static_cast<int>(d.run_samples.size());
  if (runs >= 3) {
    for (int r = 0; r < runs; ++r)
      folds.push_back({{d.run_samples[static_cast<std::size_t>(r)]}, d.runs[static_cast<std::size_t>(r)]});
    return folds;
  }
  constexpr int kParts = 3;
  for (int part = 0; part < kParts; ++part) {
    Fold f;
    f.name = fmt::format("part {}/{} of every run", part + 1, kParts);
    for (const ColumnRange& run : d.run_samples) {
      const int begin = run.begin + run.count * part / kParts;
      const int end = run.begin + run.count * (part + 1) / kParts;
      f.samples.push_back({begin, end - begin});
    }
    folds.push_back(f);
  }
  return folds;
}

GramSet::GramSet(const Design& d, std::vector<Fold> folds) : folds_(std::move(folds)) {
  const Eigen::Index p = d.columns.cols();
  for (const Fold& f : folds_) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(p, p);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(p);
    double rr = 0.0;
    int n = 0;
    for (const ColumnRange& s : f.samples) {
      if (s.count <= 0) continue;  // a run too short to split in three: nothing of it here (Eigen divides by its size)
      const auto C = d.columns.middleRows(3 * s.begin, 3 * s.count);
      const auto r = d.residual.segment(3 * s.begin, 3 * s.count);
      H.selfadjointView<Eigen::Lower>().rankUpdate(C.transpose());
      g += C.transpose() * r;
      rr += r.squaredNorm();
      n += 3 * s.count;
    }
    H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
    H_.push_back(std::move(H));
    g_.push_back(std::move(g));
    rr_.push_back(rr);
    n_.push_back(n);
  }
}

GramSet GramSet::WithAppendedColumns(const Design& d, const Eigen::MatrixXd& extra) const {
  GramSet out = *this;
  const Eigen::Index p = d.columns.cols(), m = extra.cols();
  for (std::size_t k = 0; k < folds_.size(); ++k) {
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(p, m), D = Eigen::MatrixXd::Zero(m, m);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(m);
    for (const ColumnRange& s : folds_[k].samples) {
      if (s.count <= 0) continue;  // as in the constructor
      const auto C = d.columns.middleRows(3 * s.begin, 3 * s.count);
      const auto X = extra.middleRows(3 * s.begin, 3 * s.count);
      const auto r = d.residual.segment(3 * s.begin, 3 * s.count);
      B.noalias() += C.transpose() * X;
      D.noalias() += X.transpose() * X;
      e.noalias() += X.transpose() * r;
    }
    Eigen::MatrixXd H(p + m, p + m);
    H << H_[k], B, B.transpose(), D;
    out.H_[k] = std::move(H);
    Eigen::VectorXd g(p + m);
    g << g_[k], e;
    out.g_[k] = std::move(g);
  }
  return out;
}

std::vector<int> GramSet::AllFolds() const {
  std::vector<int> all;
  for (int k = 0; k < folds(); ++k) all.push_back(k);
  return all;
}

std::vector<int> GramSet::AllBut(int fold) const {
  std::vector<int> rest;
  for (int k = 0; k < folds(); ++k) {
    if (k != fold) rest.push_back(k);
  }
  return rest;
}

Eigen::MatrixXd GramSet::NormalMatrix(const Columns& columns, const std::vector<int>& folds,
                                      const Eigen::VectorXd& prior_weight) const {
  const Eigen::Index m = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m);
  for (int f : folds) {
    const Eigen::MatrixXd& H = H_[static_cast<std::size_t>(f)];
    for (Eigen::Index a = 0; a < m; ++a) {
      for (Eigen::Index b = 0; b < m; ++b)
        A(a, b) += H(columns[static_cast<std::size_t>(a)], columns[static_cast<std::size_t>(b)]);
    }
  }
  for (Eigen::Index a = 0; a < m; ++a) A(a, a) += prior_weight(columns[static_cast<std::size_t>(a)]);
  return A;
}

namespace {

// Solves A x = b for symmetric positive semi-definite A, Jacobi-scaled,
// dropping directions the data does not determine (relative eigenvalue
// below 1e-12): those parameters stay at zero rather than blowing up.
Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd d = A.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd S = d.asDiagonal() * A * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double cutoff = lambda.maxCoeff() * 1e-12;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(lambda.size());
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    if (lambda(k) > cutoff) inv(k) = 1.0 / lambda(k);
  }
  return d.asDiagonal() * (eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose()) * d.asDiagonal();
}

}  // namespace

Eigen::VectorXd GramSet::Solve(const Columns& columns, const std::vector<int>& train,
                               const Eigen::VectorXd& prior_weight) const {
  const Eigen::Index m = static_cast<Eigen::Index>(columns.size());
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
  for (int f : train) {
    for (Eigen::Index a = 0; a < m; ++a) b(a) += g_[static_cast<std::size_t>(f)](columns[static_cast<std::size_t>(a)]);
  }
  return PseudoInverse(NormalMatrix(columns, train, prior_weight)) * b;
}

double GramSet::Sse(const Columns& columns, const Eigen::VectorXd& x, const std::vector<int>& folds) const {
  double sse = 0.0;
  const Eigen::Index m = static_cast<Eigen::Index>(columns.size());
  for (int f : folds) {
    const std::size_t k = static_cast<std::size_t>(f);
    double xg = 0.0, xHx = 0.0;
    for (Eigen::Index a = 0; a < m; ++a) {
      const int ca = columns[static_cast<std::size_t>(a)];
      xg += x(a) * g_[k](ca);
      for (Eigen::Index b = 0; b < m; ++b) xHx += x(a) * H_[k](ca, columns[static_cast<std::size_t>(b)]) * x(b);
    }
    sse += rr_[k] - 2.0 * xg + xHx;
  }
  return std::max(0.0, sse);
}

int GramSet::Residuals(const std::vector<int>& folds) const {
  int n = 0;
  for (int f : folds) n += n_[static_cast<std::size_t>(f)];
  return n;
}

Eigen::MatrixXd GramSet::Gram(const Columns& a, const Columns& b, const std::vector<int>& folds) const {
  Eigen::MatrixXd block =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(a.size()), static_cast<Eigen::Index>(b.size()));
  for (int f : folds) {
    const Eigen::MatrixXd& H = H_[static_cast<std::size_t>(f)];
    for (std::size_t i = 0; i < a.size(); ++i) {
      for (std::size_t j = 0; j < b.size(); ++j)
        block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) += H(a[i], b[j]);
    }
  }
  return block;
}

Eigen::MatrixXd GramSet::Covariance(const Columns& columns, const std::vector<int>& train,
                                    const Eigen::VectorXd& prior_weight, double sigma2) const {
  return sigma2 * PseudoInverse(NormalMatrix(columns, train, prior_weight));
}

Eigen::VectorXd PriorWeights(const Design& d, double sigma2) {
  Eigen::VectorXd w = Eigen::VectorXd::Zero(d.parameters());
  for (Effect e : AllEffects()) {
    const ColumnRange& r = d.Of(e);
    w.segment(r.begin, r.count).setConstant(sigma2 / (PriorSigma(e) * PriorSigma(e)));
  }
  return w;
}

double PriorVariance(const Design& d, double noise_floor_rms_m) {
  const double sigma_axis = std::max(noise_floor_rms_m / std::sqrt(3.0), 1e-8);
  const Eigen::VectorXd r = ResidualWhereTheLegsStood(d);
  const Eigen::MatrixXd frame = d.columns(Eigen::all, ColumnsOf(d, {}));
  const double misfit = (r - frame * frame.colPivHouseholderQr().solve(r)).squaredNorm() /
                        static_cast<double>(std::max<Eigen::Index>(1, r.size()));
  return std::max(sigma_axis * sigma_axis, misfit);
}

Columns ColumnsOf(const Design& d, const std::vector<Effect>& effects) {
  Columns c;
  for (int k = 0; k < d.frame.count; ++k) c.push_back(d.frame.begin + k);
  for (int k = 0; k < d.nuisance.count; ++k) c.push_back(d.nuisance.begin + k);
  for (Effect e : effects) {
    const ColumnRange& r = d.Of(e);
    for (int k = 0; k < r.count; ++k) c.push_back(r.begin + k);
  }
  return c;
}

double HeldOutMse(const GramSet& gram, const Columns& columns, const Eigen::VectorXd& prior_weight) {
  double sse = 0.0;
  for (int f = 0; f < gram.folds(); ++f)
    sse += gram.Sse(columns, gram.Solve(columns, gram.AllBut(f), prior_weight), {f});
  return sse / std::max(1, gram.Residuals(gram.AllFolds()));
}

Eigen::VectorXd JackknifeSigma(const GramSet& gram, const Columns& columns, const Eigen::VectorXd& prior_weight) {
  const int g = gram.folds();
  const auto p = static_cast<Eigen::Index>(columns.size());
  if (g < 2) return Eigen::VectorXd::Zero(p);
  Eigen::MatrixXd theta(p, g);
  for (int k = 0; k < g; ++k) theta.col(k) = gram.Solve(columns, gram.AllBut(k), prior_weight);
  const Eigen::MatrixXd centred = theta.colwise() - theta.rowwise().mean();
  return ((g - 1.0) / g * centred.rowwise().squaredNorm()).cwiseSqrt();
}

double CorrelationInflation(const Eigen::VectorXd& r) {
  double rr = 0.0, lag = 0.0;
  for (Eigen::Index k = 0; k < r.size(); ++k) {
    rr += r(k) * r(k);
    if (k + 3 < r.size()) lag += r(k) * r(k + 3);
  }
  const double rho = rr > 0.0 ? std::clamp(lag / rr, 0.0, 0.99) : 0.0;
  return (1.0 + rho) / (1.0 - rho);
}

Coefficient FitCoefficient(const Design& d, const GramSet& gram, const Columns& columns, int column,
                           const Eigen::VectorXd& prior_weight) {
  const auto at = std::find(columns.begin(), columns.end(), column);
  if (at == columns.end()) throw std::invalid_argument(fmt::format("column {} is not among those fitted", column));
  const Eigen::Index k = at - columns.begin();
  const std::vector<int> all = gram.AllFolds();
  const Eigen::VectorXd theta = gram.Solve(columns, all, prior_weight);
  const double sigma2 =
      gram.Sse(columns, theta, all) / std::max(1, gram.Residuals(all) - static_cast<int>(columns.size()));
  const double variance = gram.Covariance(columns, all, prior_weight, sigma2)(k, k);
  const Eigen::VectorXd rest = d.residual - d.columns(Eigen::all, columns) * theta;
  return {theta(k), std::sqrt(std::max(0.0, variance) * CorrelationInflation(rest))};
}

}  // namespace edsp::gap
