#pragma once
// Least squares on the linearised design, from per-fold normal equations:
// the Gram matrix of every column is summed once per fold, after which any
// subset of columns fitted on any set of folds, and its squared error on any
// other fold, costs a few small dense solves. That is what makes forward
// selection with cross-validation across runs cheap.

#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

using Columns = std::vector<int>;  // indices into Design::columns

struct Fold {
  std::vector<ColumnRange> samples;  // sample ranges held out together
  std::string name;                  // the run (or "run part k/n")
};

// Folds for cross-validation: one per run with 3 runs or more; otherwise
// each run cut into thirds in time.
std::vector<Fold> MakeFolds(const Design& design);

class GramSet {
 public:
  GramSet(const Design& design, std::vector<Fold> folds);
  // The same folds with `extra` (3 rows per sample of `design`, the design
  // this set was built on) appended after the design's columns: their
  // indices are design.parameters() onwards. Only the new blocks are
  // computed, not the whole Gram matrix again.
  GramSet WithAppendedColumns(const Design& design, const Eigen::MatrixXd& extra) const;

  int folds() const { return static_cast<int>(folds_.size()); }
  const Fold& fold(int k) const { return folds_[static_cast<std::size_t>(k)]; }
  std::vector<int> AllFolds() const;
  std::vector<int> AllBut(int fold) const;

  // θ for `columns` on the folds `train`, with a ridge `prior_weight` per
  // design column (σ_meas²/σ_prior², 0 for none) against null directions.
  Eigen::VectorXd Solve(const Columns& columns, const std::vector<int>& train,
                        const Eigen::VectorXd& prior_weight) const;
  // Sum of squared residuals of that θ on `folds`, and how many residuals.
  double Sse(const Columns& columns, const Eigen::VectorXd& theta, const std::vector<int>& folds) const;
  int Residuals(const std::vector<int>& folds) const;
  // Σ over `folds` of the Gram block CₐᵀC_b.
  Eigen::MatrixXd Gram(const Columns& a, const Columns& b, const std::vector<int>& folds) const;
  // Covariance of θ (σ² (H + Λ)⁻¹), for uncertainties and correlations.
  Eigen::MatrixXd Covariance(const Columns& columns, const std::vector<int>& train, const Eigen::VectorXd& prior_weight,
                             double sigma2) const;

 private:
  Eigen::MatrixXd NormalMatrix(const Columns& columns, const std::vector<int>& folds,
                               const Eigen::VectorXd& prior_weight) const;
  std::vector<Fold> folds_;
  std::vector<Eigen::MatrixXd> H_;  // per fold: CᵀC over all design columns
  std::vector<Eigen::VectorXd> g_;  // Cᵀr
  std::vector<double> rr_;          // rᵀr
  std::vector<int> n_;              // residuals
};

// The effects' ridge for a measurement σ² per axis: σ²/σ_prior² on each
// effect's columns (calibration::PriorSigma), none on the frame's and the
// nuisance's.
Eigen::VectorXd PriorWeights(const Design& design, double sigma2);

// The σ² per axis that prior is weighed with: the larger of the noise
// floor's and the misfit of the frame (and nuisance) alone, taken where the
// legs stood (ResidualWhereTheLegsStood). Against what the model does not
// yet explain, not the noise alone, a systematic misfit cannot push poorly
// excited parameters (joint centres seen from a single axis) far beyond
// real rigs; a soft drive loop's recorded lag is motion, not misfit, and
// counted as one it would shrink every parameter beside it.
double PriorVariance(const Design& design, double noise_floor_rms_m);

// Every column of the frame, of the nuisance and of the listed effects.
Columns ColumnsOf(const Design& design, const std::vector<Effect>& effects);

// Mean squared held-out residual per coordinate of `columns`, each fold
// predicted by a fit on the others: what selection and the searches over
// the bases' non-linear parameters compare.
double HeldOutMse(const GramSet& gram, const Columns& columns, const Eigen::VectorXd& prior_weight);

// The delete-a-group jackknife's standard error of θ for `columns` (the
// ridge `prior_weight` as in Solve): √((g − 1)/g · Σ_k (θ₍ₖ₎ − θ̄)²) over
// the g fits that each leave one fold out. It measures how far the
// estimate moves with the data it is fitted on, which the formal σ (the
// model taken as the truth) cannot: what the model leaves out of the rig
// moves a parameter with the motion, so with one fold per run (each run
// its own motion) it sees that. Zero with fewer than two folds.
Eigen::VectorXd JackknifeSigma(const GramSet& gram, const Columns& columns, const Eigen::VectorXd& prior_weight);

// (1 + ρ)/(1 − ρ), ρ the lag-1 autocorrelation of a residual of 3 rows per
// sample (clamped to [0, 0.99]): how much a fit's variance grows when its
// residual is not white.
double CorrelationInflation(const Eigen::VectorXd& residual);

// One coefficient of a fit on every fold, and its 1-σ: the covariance's,
// with σ² the fit's residual variance, grown for that residual's
// autocorrelation. A residual that is not white (a mode, a misfit) holds
// fewer independent samples than rows: the variance grows by
// (1 + ρ)/(1 − ρ), ρ its lag-1 autocorrelation along each axis (3 rows per
// sample), as for an AR(1) series. How the nuisances that are reported, not selected (the
// tracker's clock offset and drift), get their uncertainty.
struct Coefficient {
  double value = 0.0;
  double sigma = 0.0;
};
Coefficient FitCoefficient(const Design& design, const GramSet& gram, const Columns& columns, int column,
                           const Eigen::VectorXd& prior_weight);

}  // namespace edsp::gap
