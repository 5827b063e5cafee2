// Fits from per-fold Gram matrices against the same least squares solved
// directly on the stacked rows (an independent computation).
#include <random>

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
    const Eigen::VectorXd held = d.residual.segment(3 * f * per_run, 3 * per_run) -
                                 d.columns.middleRows(3 * f * per_run, 3 * per_run) * direct;
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

}  // namespace
}  // namespace edsp::gap
