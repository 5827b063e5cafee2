#include "edsp/diagnosis/structural_mode_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/structure_nuisance.h"

namespace edsp::gap {

namespace {

// The band searched: below 1 Hz a "mode" is the motions' own rate; above
// 25 Hz a mount is stiff enough that its sway is under a micrometre.
constexpr double kLowestHz = 1.0, kHighestHz = 25.0;
// A lightly damped mode fits only within about ±ζ of its frequency (at ζ
// 0.03 a mode 4% off predicts the ringing worse than none): the screen
// steps by 1.2%, at a damping between those of real mounts.
constexpr double kScreenRatio = 1.012;
constexpr double kScreenDamping = 0.02;
constexpr int kRefined = 4;  // the screen's best few, refined on held-out runs
constexpr double kDampings[] = {0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2};
constexpr int kGoldenSteps = 10;  // a bracket of two screen steps shrinks to 0.02%

// The frame and the selected effects, once; each candidate mode adds its
// three columns to their Gram matrices (a few products over the rows, not
// the whole design's Gram matrix again).
class ModeScore {
 public:
  ModeScore(const Design& full, const std::vector<Effect>& selected, double sigma2)
      : full_(full),
        kept_(KeepOnly(full, selected)),
        gram_(kept_, MakeFolds(kept_)),
        cols_(ColumnsOf(kept_, AllEffects())),
        prior_(PriorWeights(kept_, sigma2)) {}
  double Without() const { return HeldOutMse(gram_, cols_, prior_); }
  double With(double hz, double zeta) const {
    const GramSet with = gram_.WithAppendedColumns(kept_, SwayColumns(full_, hz, zeta));
    Columns cols = cols_;
    const int p = kept_.parameters();
    for (int k = 0; k < 3; ++k) cols.push_back(p + k);
    Eigen::VectorXd prior = Eigen::VectorXd::Zero(p + 3);
    prior.head(p) = prior_;
    return HeldOutMse(with, cols, prior);
  }
  // The in-sample residual of the frame and the selected effects.
  Eigen::VectorXd Residual() const {
    const Eigen::VectorXd theta = gram_.Solve(cols_, gram_.AllFolds(), prior_);
    return kept_.residual - kept_.columns(Eigen::all, cols_) * theta;
  }

 private:
  const Design& full_;
  Design kept_;
  GramSet gram_;
  Columns cols_;
  Eigen::VectorXd prior_;
};

// How much of `residual` the mode's sway takes up (its three columns fitted
// to it alone): a screen, cheap enough for a fine grid.
double SwayShare(const Design& d, const Eigen::VectorXd& residual, double hz) {
  const Eigen::MatrixXd X = SwayColumns(d, hz, kScreenDamping);
  const Eigen::Vector3d Xr = X.transpose() * residual;
  const Eigen::Matrix3d XX = X.transpose() * X;
  return Xr.dot(XX.ldlt().solve(Xr));
}

// The screen's best local maxima, best first, and the spectral peak.
std::vector<double> Candidates(const ModeScore& score, const Design& d, double peak_hz) {
  const Eigen::VectorXd residual = score.Residual();
  std::vector<double> grid, share;
  for (double hz = kLowestHz; hz <= kHighestHz; hz *= kScreenRatio) {
    grid.push_back(hz);
    share.push_back(SwayShare(d, residual, hz));
  }
  std::vector<std::size_t> peaks;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const bool left = k == 0 || share[k] >= share[k - 1], right = k + 1 == grid.size() || share[k] >= share[k + 1];
    if (left && right) peaks.push_back(k);
  }
  std::sort(peaks.begin(), peaks.end(), [&](std::size_t a, std::size_t b) { return share[a] > share[b]; });
  std::vector<double> out;
  for (std::size_t k = 0; k < peaks.size() && static_cast<int>(k) < kRefined; ++k) out.push_back(grid[peaks[k]]);
  if (peak_hz > kLowestHz && peak_hz < kHighestHz) out.push_back(peak_hz);
  return out;
}

// Golden section on the held-out error within a screen step of `hz`.
std::pair<double, double> Refine(const ModeScore& score, double hz, double zeta) {
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = hz / kScreenRatio, hi = hz * kScreenRatio;
  double a = hi - kInvPhi * (hi - lo), b = lo + kInvPhi * (hi - lo);
  double fa = score.With(a, zeta), fb = score.With(b, zeta);
  for (int k = 0; k < kGoldenSteps; ++k) {
    if (fa < fb) {
      hi = b, b = a, fb = fa, a = hi - kInvPhi * (hi - lo), fa = score.With(a, zeta);
    } else {
      lo = a, a = b, fa = fb, b = lo + kInvPhi * (hi - lo), fb = score.With(b, zeta);
    }
  }
  return fa < fb ? std::pair{a, fa} : std::pair{b, fb};
}

}  // namespace

StructuralModeChoice ChooseStructuralMode(const Design& d, const std::vector<Effect>& selected, double sigma2,
                                          double peak_hz) {
  const ModeScore score(d, selected, sigma2);
  const double without = score.Without();
  StructuralModeChoice choice;
  double best_mse = std::numeric_limits<double>::infinity();
  for (double hz : Candidates(score, d, peak_hz)) {
    const auto [at, mse] = Refine(score, hz, kScreenDamping);
    if (mse < best_mse) best_mse = mse, choice.hz = at, choice.damping = kScreenDamping;
  }
  if (choice.hz <= 0.0) return choice;
  for (double zeta : kDampings) {
    if (zeta == kScreenDamping) continue;
    const double m = score.With(choice.hz, zeta);
    if (m < best_mse) best_mse = m, choice.damping = zeta;
  }
  // The frequency again at that damping (a wider peak's best frequency can differ).
  const auto [at, mse] = Refine(score, choice.hz, choice.damping);
  if (mse < best_mse) best_mse = mse, choice.hz = at;
  choice.cv_gain = without > 0.0 ? (without - best_mse) / without : 0.0;
  return choice;
}

}  // namespace edsp::gap
