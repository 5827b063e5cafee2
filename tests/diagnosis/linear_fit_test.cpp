// Fits from per-fold Gram matrices against the same least squares solved
// directly on the stacked rows (an independent computation), and a
// coefficient's σ against its scatter over noise draws.
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/QR>
#include <gtest/gtest.h>

#include "edsp/diagnosis/linear_fit.h"

namespace edsp::gap {
namespace {

TEST(GramSet, HeldOutErrorsEqualDirectLeastSquares) {
  Design d;
  const int per_run = 200, runs = 4, params = 6 + 3;
  d.columns.resize(3 * per_run * runs, params);
  d.residual.resize(3 * per_run * runs);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index i = 0; i < d.columns.size(); ++i) d.columns.data()[i] = n(rng);
  Eigen::VectorXd truth(params);
  for (int k = 0; k < params; ++k) truth(k) = n(rng);
  d.residual = d.columns * truth;
  for (Eigen::Index i = 0; i < d.residual.size(); ++i) d.residual(i) += 0.1 * n(rng);
  for (int r = 0; r < runs; ++r) {
    d.run_samples.push_back({r * per_run, per_run});
    d.runs.push_back("run" + std::to_string(r));
  }
  const GramSet gram(d, MakeFolds(d));
  ASSERT_EQ(gram.folds(), runs);
  Columns cols;
  for (int k = 0; k < params; ++k) cols.push_back(k);
  const Eigen::VectorXd no_prior = Eigen::VectorXd::Zero(params);
  for (int f = 0; f < runs; ++f) {
    // Direct: stack the other runs' rows and solve with QR.
    Eigen::MatrixXd A(3 * per_run * (runs - 1), params);
    Eigen::VectorXd b(3 * per_run * (runs - 1));
    int at = 0;
    for (int r = 0; r < runs; ++r) {
      if (r == f) continue;
      A.middleRows(at, 3 * per_run) = d.columns.middleRows(3 * r * per_run, 3 * per_run);
      b.segment(at, 3 * per_run) = d.residual.segment(3 * r * per_run, 3 * per_run);
      at += 3 * per_run;
    }
    const Eigen::VectorXd direct = A.colPivHouseholderQr().solve(b);
    const Eigen::VectorXd fast = gram.Solve(cols, gram.AllBut(f), no_prior);
    EXPECT_LT((direct - fast).norm(), 1e-9);
    const Eigen::VectorXd held =
        d.residual.segment(3 * f * per_run, 3 * per_run) - d.columns.middleRows(3 * f * per_run, 3 * per_run) * direct;
    EXPECT_NEAR(gram.Sse(cols, fast, {f}), held.squaredNorm(), 1e-9 * held.squaredNorm());
  }
}

TEST(GramSet, FewRunsAreCutIntoThirdsInTime) {
  Design d;
  d.run_samples = {{0, 30}, {30, 60}};
  d.runs = {"a", "b"};
  const std::vector<Fold> folds = MakeFolds(d);
  ASSERT_EQ(folds.size(), 3u);
  EXPECT_EQ(folds[1].samples[0].begin, 10);
  EXPECT_EQ(folds[1].samples[1].begin, 50);
  EXPECT_EQ(folds[2].samples[1].count, 20);
}

// A run of one or two samples (a recording that began at the end of the
// motion before) has nothing in some thirds: those folds take nothing of
// it, and the fit is the fit of the long run (Eigen's product of an empty
// block divided by zero: SIGFPE in edsp-gap evaluate).
TEST(GramSet, ARunTooShortToSplitAddsNothingToAFold) {
  Design d;
  const int long_run = 300, params = 104;  // as many columns as a diagnosis has: Eigen blocks the product
  d.columns.resize(3 * (long_run + 1), params);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index i = 0; i < d.columns.size(); ++i) d.columns.data()[i] = n(rng);
  Eigen::VectorXd truth(params);
  for (int k = 0; k < params; ++k) truth(k) = n(rng);
  d.residual = d.columns * truth;
  d.run_samples = {{0, 1}, {1, long_run}};
  d.runs = {"end of the motion before", "Rx"};
  const GramSet gram(d, MakeFolds(d));
  ASSERT_EQ(gram.folds(), 3);
  Columns cols;
  for (int k = 0; k < params; ++k) cols.push_back(k);
  const Eigen::VectorXd fit = gram.Solve(cols, gram.AllBut(0), Eigen::VectorXd::Zero(params));
  EXPECT_LT((fit - truth).norm(), 1e-9 * truth.norm());
}

// Twelve runs of random columns; the last column's coefficient is the
// same in every run, or moves from run to run by `spread` (what a model
// that is not the rig's does to a parameter as the motion changes).
Design RunsWithAMovingCoefficient(double spread, std::uint64_t seed) {
  Design d;
  const int per_run = 50, runs = 12, params = 6 + 2;
  d.columns.resize(3 * per_run * runs, params);
  d.residual.resize(3 * per_run * runs);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index i = 0; i < d.columns.size(); ++i) d.columns.data()[i] = n(rng);
  for (int r = 0; r < runs; ++r) {
    d.run_samples.push_back({r * per_run, per_run});
    d.runs.push_back("run" + std::to_string(r));
    Eigen::VectorXd truth = Eigen::VectorXd::Ones(params);
    truth(params - 1) += spread * (r % 2 == 0 ? 1.0 : -1.0);
    const auto rows = Eigen::seqN(3 * r * per_run, 3 * per_run);
    d.residual(rows) = d.columns(rows, Eigen::all) * truth;
  }
  for (Eigen::Index i = 0; i < d.residual.size(); ++i) d.residual(i) += 0.1 * n(rng);
  return d;
}

Columns AllColumns(const Design& d) {
  Columns cols;
  for (int k = 0; k < d.columns.cols(); ++k) cols.push_back(k);
  return cols;
}

// The jackknife against its definition evaluated on fits solved directly
// on the stacked rows with QR, one per run left out.
TEST(JackknifeSigma, EqualsTheSpreadOfDirectLeaveOneRunOutFits) {
  const Design d = RunsWithAMovingCoefficient(0.05, 21);
  const std::vector<Fold> folds = MakeFolds(d);
  ASSERT_EQ(folds.size(), 12u);
  const GramSet gram(d, folds);
  const Columns cols = AllColumns(d);
  const int g = static_cast<int>(folds.size());
  Eigen::MatrixXd theta(d.columns.cols(), g);
  for (int k = 0; k < g; ++k) {
    std::vector<Eigen::Index> rows;
    for (int j = 0; j < g; ++j) {
      if (j == k) continue;
      for (const ColumnRange& s : folds[static_cast<std::size_t>(j)].samples) {
        for (Eigen::Index i = 3 * s.begin; i < 3 * (s.begin + s.count); ++i) rows.push_back(i);
      }
    }
    const Eigen::MatrixXd A = d.columns(rows, Eigen::all);
    const Eigen::VectorXd b = d.residual(rows);
    theta.col(k) = A.colPivHouseholderQr().solve(b);
  }
  const Eigen::VectorXd mean = theta.rowwise().mean();
  const Eigen::VectorXd jack = JackknifeSigma(gram, cols, Eigen::VectorXd::Zero(d.columns.cols()));
  for (Eigen::Index p = 0; p < theta.rows(); ++p) {
    const double direct =
        std::sqrt((g - 1.0) / g * (theta.row(p).transpose() - Eigen::VectorXd::Constant(g, mean(p))).squaredNorm());
    EXPECT_NEAR(jack(p), direct, 1e-9 * direct) << "column " << p;
  }
}

// Where the model is the truth, the jackknife's σ is the formal one (twelve
// runs: within a factor of 1.6 either way); where a coefficient moves from
// run to run by 20 formal σ, its jackknife σ sees it and the formal σ,
// which takes the model for the truth, does not.
TEST(JackknifeSigma, IsTheFormalSigmaWhereTheModelHoldsAndGrowsWhereItDoesNot) {
  for (const double spread : {0.0, 0.2}) {
    const Design d = RunsWithAMovingCoefficient(spread, 22);
    const GramSet gram(d, MakeFolds(d));
    const Columns cols = AllColumns(d);
    const Eigen::VectorXd none = Eigen::VectorXd::Zero(d.columns.cols());
    const Eigen::VectorXd theta = gram.Solve(cols, gram.AllFolds(), none);
    const double sigma2 =
        (d.residual - d.columns * theta).squaredNorm() / static_cast<double>(d.residual.size() - d.columns.cols());
    const Eigen::VectorXd formal = gram.Covariance(cols, gram.AllFolds(), none, sigma2).diagonal().cwiseSqrt();
    const Eigen::VectorXd jack = JackknifeSigma(gram, cols, none);
    const Eigen::Index moving = d.columns.cols() - 1;
    for (Eigen::Index p = 0; p < moving; ++p) {
      EXPECT_GT(jack(p), formal(p) / 1.6) << "spread " << spread << ", column " << p;
      EXPECT_LT(jack(p), formal(p) * 1.6) << "spread " << spread << ", column " << p;
    }
    if (spread == 0.0) {
      EXPECT_LT(jack(moving), formal(moving) * 1.6);
    } else {
      EXPECT_GT(spread, 20.0 * formal(moving));
      EXPECT_GT(jack(moving), 0.25 * spread) << "formal " << formal(moving);
    }
  }
}

// A slow signal (a velocity-like column, period 200 samples) in noise that
// is white, and in noise that is AR(1) along each axis (ρ = 0.8: 9 times
// the variance of a white fit's coefficient). The reported σ against the
// coefficient's scatter over many noise draws, a Monte Carlo truth the
// formula does not see; and the value against QR on the stacked rows.
TEST(FitCoefficient, ItsSigmaIsTheScatterOverNoiseDrawsWhiteOrCorrelated) {
  const int samples = 1000, draws = 400;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double rho : {0.0, 0.8}) {
    Design d;
    d.columns.resize(3 * samples, 2);
    for (int k = 0; k < samples; ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        d.columns(3 * k + axis, 0) = std::sin(2.0 * M_PI * k / 200.0 + axis);
        d.columns(3 * k + axis, 1) = 1.0;
      }
    }
    d.run_samples = {{0, samples / 2}, {samples / 2, samples / 2}};
    d.runs = {"a", "b"};
    const Columns cols = {0, 1};
    const Eigen::VectorXd no_prior = Eigen::VectorXd::Zero(2);
    double sum = 0.0, sum2 = 0.0, reported = 0.0;
    for (int draw = 0; draw < draws; ++draw) {
      d.residual.resize(3 * samples);
      double e[3] = {n(rng), n(rng), n(rng)};
      for (int k = 0; k < samples; ++k) {
        for (int axis = 0; axis < 3; ++axis) {
          e[axis] = rho * e[axis] + std::sqrt(1.0 - rho * rho) * n(rng);
          d.residual(3 * k + axis) = 2.0 * d.columns(3 * k + axis, 0) + 0.5 + e[axis];
        }
      }
      const Coefficient c = FitCoefficient(d, GramSet(d, MakeFolds(d)), cols, 0, no_prior);
      if (draw == 0) {
        const Eigen::VectorXd direct = d.columns.colPivHouseholderQr().solve(d.residual);
        EXPECT_NEAR(c.value, direct(0), 1e-9);
      }
      sum += c.value, sum2 += c.value * c.value, reported += c.sigma;
    }
    const double mean = sum / draws, scatter = std::sqrt(sum2 / draws - mean * mean);
    EXPECT_NEAR(mean, 2.0, 4.0 * scatter / std::sqrt(draws)) << "rho " << rho;
    // The scatter of 400 draws is known to ±3.5%; the AR(1) inflation is
    // an approximation for a regressor slow beside the noise's memory.
    EXPECT_NEAR(reported / draws / scatter, 1.0, 0.15) << "rho " << rho << ": scatter " << scatter;
  }
}

TEST(FitCoefficient, AColumnNotFittedIsAnError) {
  Design d;
  d.columns = Eigen::MatrixXd::Ones(3, 2);
  d.residual = Eigen::VectorXd::Ones(3);
  d.run_samples = {{0, 1}};
  d.runs = {"a"};
  EXPECT_THROW(FitCoefficient(d, GramSet(d, {{{{0, 1}}, "a"}}), {0}, 1, Eigen::VectorXd::Zero(2)),
               std::invalid_argument);
}

}  // namespace
}  // namespace edsp::gap
