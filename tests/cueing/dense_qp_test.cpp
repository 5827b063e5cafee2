// The cueing's QP solver (ADMM, cueing/dense_qp.h) against IPOPT (an
// interior-point method, coinor-libipopt, written apart from it) on the
// same problems: random convex QPs with inequality rows, boxes and rows
// with one side open, and the model-predictive cueing's own problems taken
// from a braking manoeuvre. On the random problems both reach the same
// optimum: the objective within 1e-6 of its scale, the solution within
// 1e-3 of its, ADMM's within 1e-5 of the constraints. The cueing's problems
// are ill-conditioned (the horizon's last jerks barely change the cost)
// and ADMM's last digits come slowly there: the optimum's value within
// 0.2% of its scale and every row within 1e-3 of its bound (1 mm, 1 mrad,
// 1 mm/s, …; half a percent of the narrowest box the shares give these
// problems, and the leg margin is 5% of a leg's room), the solution free to
// differ along the directions the cost hardly sees.
#include "edsp/cueing/dense_qp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/manoeuvre.h"
#include "edsp/cueing/mpc_cueing.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

struct Qp {
  Eigen::MatrixXd h, a;
  Eigen::VectorXd g, lower, upper;
};

// The QP as IPOPT's nonlinear programme: f = ½xᵀHx + gᵀx, g(x) = Ax.
class IpoptQp : public Ipopt::TNLP {
 public:
  explicit IpoptQp(const Qp& qp) : qp_(qp) {}
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = static_cast<Ipopt::Index>(qp_.h.rows());
    m = static_cast<Ipopt::Index>(qp_.a.rows());
    nnz_jac = n * m;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* xl, Ipopt::Number* xu, Ipopt::Index m, Ipopt::Number* gl,
                       Ipopt::Number* gu) override {
    for (Ipopt::Index i = 0; i < n; ++i) xl[i] = -2e19, xu[i] = 2e19;
    for (Ipopt::Index i = 0; i < m; ++i) {
      gl[i] = std::isfinite(qp_.lower(i)) ? qp_.lower(i) : -2e19;
      gu[i] = std::isfinite(qp_.upper(i)) ? qp_.upper(i) : 2e19;
    }
    return true;
  }
  bool get_starting_point(Ipopt::Index n, bool, Ipopt::Number* x, bool, Ipopt::Number*, Ipopt::Number*, Ipopt::Index,
                          bool, Ipopt::Number*) override {
    for (Ipopt::Index i = 0; i < n; ++i) x[i] = 0.0;
    return true;
  }
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    const Eigen::Map<const Eigen::VectorXd> v(x, n);
    f = 0.5 * v.dot(qp_.h * v) + qp_.g.dot(v);
    return true;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* grad) override {
    const Eigen::Map<const Eigen::VectorXd> v(x, n);
    Eigen::Map<Eigen::VectorXd>(grad, n) = qp_.h * v + qp_.g;
    return true;
  }
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index m, Ipopt::Number* g) override {
    Eigen::Map<Eigen::VectorXd>(g, m) = qp_.a * Eigen::Map<const Eigen::VectorXd>(x, n);
    return true;
  }
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number*, bool, Ipopt::Index m, Ipopt::Index, Ipopt::Index* rows,
                  Ipopt::Index* cols, Ipopt::Number* values) override {
    Ipopt::Index k = 0;
    for (Ipopt::Index i = 0; i < m; ++i) {
      for (Ipopt::Index j = 0; j < n; ++j, ++k) {
        if (values == nullptr) {
          rows[k] = i, cols[k] = j;
        } else {
          values[k] = qp_.a(i, j);
        }
      }
    }
    return true;
  }
  bool eval_h(Ipopt::Index n, const Ipopt::Number*, bool, Ipopt::Number factor, Ipopt::Index, const Ipopt::Number*,
              bool, Ipopt::Index, Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override {
    Ipopt::Index k = 0;
    for (Ipopt::Index i = 0; i < n; ++i) {
      for (Ipopt::Index j = 0; j <= i; ++j, ++k) {
        if (values == nullptr) {
          rows[k] = i, cols[k] = j;
        } else {
          values[k] = factor * qp_.h(i, j);
        }
      }
    }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*,
                         Ipopt::Number objective, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    solved = status == Ipopt::SUCCESS;
    x_star = Eigen::Map<const Eigen::VectorXd>(x, n);
    objective_star = objective;
  }

  bool solved = false;
  Eigen::VectorXd x_star;
  double objective_star = 0.0;

 private:
  Qp qp_;
};

struct Optimum {
  Eigen::VectorXd x;
  double objective;
};

Optimum SolveWithIpopt(const Qp& qp) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetNumericValue("tol", 1e-12);
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  EXPECT_EQ(app->Initialize(), Ipopt::Solve_Succeeded);
  Ipopt::SmartPtr<IpoptQp> problem = new IpoptQp(qp);
  app->OptimizeTNLP(problem);
  EXPECT_TRUE(problem->solved);
  return {problem->x_star, problem->objective_star};
}

double Objective(const Qp& qp, const Eigen::VectorXd& x) { return 0.5 * x.dot(qp.h * x) + qp.g.dot(x); }

double Violation(const Qp& qp, const Eigen::VectorXd& x) {
  const Eigen::VectorXd ax = qp.a * x;
  return std::max((qp.lower - ax).maxCoeff(), (ax - qp.upper).maxCoeff());
}

struct Tolerance {
  double objective, violation;
  bool same_solution;
};
constexpr Tolerance kWellConditioned{1e-6, 1e-5, true};
constexpr Tolerance kIllConditioned{2e-3, 1e-3, false};

void ExpectSameOptimum(const Qp& qp, const std::string& what, const Tolerance& tolerance) {
  DenseQpSettings settings;
  settings.max_iterations = 20000;
  settings.eps_abs = settings.eps_rel = 1e-9;
  DenseQp admm(qp.h, qp.a, settings);
  const DenseQpResult& r = admm.Solve(qp.g, qp.lower, qp.upper);
  const Optimum ipopt = SolveWithIpopt(qp);
  const double scale = std::max(1.0, std::fabs(ipopt.objective));
  EXPECT_NEAR(Objective(qp, r.x), ipopt.objective, tolerance.objective * scale)
      << what << ": " << r.iterations << " iterations, residuals " << r.primal_residual << ", " << r.dual_residual;
  EXPECT_LT(Violation(qp, r.x), tolerance.violation) << what;
  if (tolerance.same_solution) {
    EXPECT_TRUE(r.converged) << what;
    EXPECT_LT((r.x - ipopt.x).cwiseAbs().maxCoeff(), 1e-3 * std::max(1.0, ipopt.x.cwiseAbs().maxCoeff())) << what;
  }
}

Qp RandomQp(std::mt19937_64& random, int n, int m) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> width(0.01, 1.0);
  Qp qp;
  const Eigen::MatrixXd root = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(random); });
  qp.h = root * root.transpose() / n + 0.01 * Eigen::MatrixXd::Identity(n, n);
  qp.a = Eigen::MatrixXd::NullaryExpr(m, n, [&] { return normal(random); });
  qp.g = 5.0 * Eigen::VectorXd::NullaryExpr(n, [&] { return normal(random); });
  const Eigen::VectorXd feasible = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.1 * normal(random); });
  const Eigen::VectorXd center = qp.a * feasible;
  qp.lower.resize(m), qp.upper.resize(m);
  for (int i = 0; i < m; ++i) {
    qp.lower(i) = center(i) - width(random);
    qp.upper(i) = center(i) + width(random);
    if (i % 7 == 3) qp.upper(i) = std::numeric_limits<double>::infinity();  // one side open
  }
  return qp;
}

TEST(DenseQp, RandomProblemsReachIpoptsOptimum) {
  std::mt19937_64 random(4401);
  for (int k = 0; k < 20; ++k) {
    const int n = 5 + 3 * (k % 8), m = 2 * n + k;
    ExpectSameOptimum(RandomQp(random, n, m), "random QP " + std::to_string(k), kWellConditioned);
  }
}

TEST(DenseQp, TheCueingsOwnProblemsReachIpoptsOptimum) {
  const PlatformModel model(Huang2021Config());
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  MpcCueing mpc(model, model.home_pose(), config.head_in_platform_m, config.perception, config.mpc,
                1.0 / config.rate_hz);
  const VehicleSeries vehicle =
      SampleManoeuvre(LoadManoeuvre(SourceDir() + "/config/manoeuvres/braking.toml"), 1.0 / config.rate_hz);
  int checked = 0;
  for (std::size_t k = 0; k < vehicle.samples.size(); ++k) {
    mpc.Step(vehicle.samples[k]);
    if (k % 997 != 0) continue;  // every channel's problem at ~1 s apart, braking and washing out
    for (const MpcChannel* channel : mpc.channels()) {
      const MpcChannel::Problem p = channel->last_problem();
      ExpectSameOptimum({p.hessian, p.constraint, p.g, p.lower, p.upper},
                        "cueing problem at sample " + std::to_string(k), kIllConditioned);
      ++checked;
    }
  }
  EXPECT_GE(checked, 20);
}

TEST(DenseQp, ABoundTheWrongWayRoundIsNamed) {
  DenseQp qp(Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(2, 2));
  try {
    qp.Solve(Eigen::VectorXd::Zero(2), Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(1.0, 0.5));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("row 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp
