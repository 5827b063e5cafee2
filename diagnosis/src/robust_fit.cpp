#include "edsp/diagnosis/robust_fit.h"

#include <ceres/ceres.h>
#include <Eigen/Geometry>

namespace edsp::gap {

namespace {

Matrix3 Rotation(const double* w) {
  const Vector3 v(w[0], w[1], w[2]);
  const double angle = v.norm();
  return angle > 0.0 ? Eigen::AngleAxisd(angle, v / angle).toRotationMatrix() : Matrix3::Identity();
}

// One tracker sample: r = point − (R0·R(δω)·(A + R0ᵀ·C·θ) + t0 + δt), with
// point − R0·A − t0 the design's residual.
class SampleCost : public ceres::CostFunction {
 public:
  SampleCost(const Design& d, const Eigen::MatrixXd& C, int sample) : d_(d), C_(C), k_(sample) {
    set_num_residuals(3);
    mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(C.cols()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* frame = parameters[0];
    const Eigen::Map<const Eigen::VectorXd> theta(parameters[1], C_.cols());
    const auto rows = C_.middleRows(3 * k_, 3);
    const Vector3 A = d_.model_point[static_cast<std::size_t>(k_)];
    const Vector3 q = A + d_.R0.transpose() * (rows * theta);
    const Vector3 measured_minus_t0 = d_.residual.segment<3>(3 * k_) + d_.R0 * A;
    auto predict = [&](const double* w) { return Vector3(d_.R0 * Rotation(w) * q); };
    const Matrix3 R = d_.R0 * Rotation(frame);
    Eigen::Map<Vector3> r(residuals);
    r = measured_minus_t0 - R * q - Vector3(frame[3], frame[4], frame[5]);
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jacobians[0]);
      for (int a = 0; a < 3; ++a) {
        double plus[3] = {frame[0], frame[1], frame[2]}, minus[3] = {frame[0], frame[1], frame[2]};
        constexpr double h = 1e-7;
        plus[a] += h;
        minus[a] -= h;
        J.col(a) = -(predict(plus) - predict(minus)) / (2.0 * h);
      }
      J.rightCols<3>() = -Matrix3::Identity();
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[1], 3, C_.cols());
      J = -(R * d_.R0.transpose()) * rows;
    }
    return true;
  }

 private:
  const Design& d_;
  const Eigen::MatrixXd& C_;
  int k_;
};

// The ridge prior as residuals √w_j·θ_j, one per parameter.
class PriorCost : public ceres::CostFunction {
 public:
  explicit PriorCost(Eigen::VectorXd sqrt_weight) : w_(std::move(sqrt_weight)) {
    set_num_residuals(static_cast<int>(w_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(w_.size()));
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    for (Eigen::Index k = 0; k < w_.size(); ++k) residuals[k] = w_(k) * parameters[0][k];
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[0], w_.size(),
                                                                                           w_.size());
      J = w_.asDiagonal();
    }
    return true;
  }

 private:
  Eigen::VectorXd w_;
};

}  // namespace

RobustFit FitRobust(const Design& d, const std::vector<int>& columns, const Eigen::VectorXd& start, double huber_m,
                    const Eigen::VectorXd& prior_weight) {
  RobustFit fit;
  fit.huber_m = huber_m;
  const Eigen::MatrixXd C = d.columns(Eigen::all, columns);
  fit.theta = start;
  fit.frame = Eigen::VectorXd::Zero(6);
  if (fit.theta.size() == 0) fit.theta = Eigen::VectorXd::Zero(1);  // Ceres needs a block; C has no columns
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::HuberLoss loss(huber_m);
  const Eigen::MatrixXd C_used = C.cols() ? C : Eigen::MatrixXd::Zero(C.rows(), 1);
  for (int k = 0; k < d.samples(); ++k) {
    problem.AddResidualBlock(new SampleCost(d, C_used, k), &loss, fit.frame.data(), fit.theta.data());
  }
  if (C.cols() == 0) {
    problem.SetParameterBlockConstant(fit.theta.data());
  } else if (prior_weight.size() > 0) {
    Eigen::VectorXd root(static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < columns.size(); ++k)
      root(static_cast<Eigen::Index>(k)) = std::sqrt(prior_weight(columns[k]));
    problem.AddResidualBlock(new PriorCost(root), nullptr, fit.theta.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 25;
  options.function_tolerance = 1e-10;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.converged = summary.termination_type == ceres::CONVERGENCE;

  fit.residual.resize(3 * d.samples());
  double sum2 = 0.0;
  for (int k = 0; k < d.samples(); ++k) {
    double r[3];
    const double* parameters[2] = {fit.frame.data(), fit.theta.data()};
    SampleCost(d, C_used, k).Evaluate(parameters, r, nullptr);
    fit.residual.segment<3>(3 * k) = Vector3(r[0], r[1], r[2]);
    sum2 += r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  }
  if (C.cols() == 0) {
    fit.theta.resize(0);
    fit.sigma.resize(0);
    fit.covariance_ok = true;
    return fit;
  }
  // Ceres assumes unit-variance residuals: scale by the residual variance.
  const double dof = std::max(1.0, 3.0 * d.samples() - static_cast<double>(C.cols() + 6));
  const double variance = sum2 / dof;
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.null_space_rank = -1;
  ceres::Covariance covariance(covariance_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{fit.theta.data(), fit.theta.data()}};
  fit.sigma = Eigen::VectorXd::Zero(fit.theta.size());
  if (covariance.Compute(blocks, &problem)) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> block(fit.theta.size(), fit.theta.size());
    covariance.GetCovarianceBlock(fit.theta.data(), fit.theta.data(), block.data());
    fit.sigma = (variance * block.diagonal()).cwiseMax(0.0).cwiseSqrt();
    fit.covariance_ok = true;
  }
  return fit;
}

}  // namespace edsp::gap
