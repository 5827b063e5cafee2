#include "edsp/diagnosis/change_point.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>
#include <tuple>

#include <boost/math/distributions/chi_squared.hpp>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/time_offset.h"

namespace edsp::gap {

const char* StepRejectionName(StepRejection why) {
  switch (why) {
    case StepRejection::kNone: return "";
    case StepRejection::kDrift: return "drift";
    case StepRejection::kStructure: return "structure";
    case StepRejection::kUndetermined: return "undetermined";
    case StepRejection::kOtherSignature: return "other_signature";
  }
  return "";
}

namespace {

constexpr int kLegSignatures = 6;
constexpr int kSignatures = kLegSignatures + 1;  // the six legs, then the tracker's frame
constexpr int kMinSideSamples = 30;

int Width(int signature) { return signature < kLegSignatures ? 1 : 6; }

// The columns a step of `signature` moves sample `k` by (3 × width).
Eigen::MatrixXd SignatureAt(const Design& d, int signature, int k) {
  if (signature < kLegSignatures) return d.point_per_leg[static_cast<std::size_t>(k)].col(signature);
  return d.columns.block(3 * k, d.frame.begin, 3, d.frame.count);
}

// The frame and every effect of the vocabulary with the diagnosis's prior:
// what a step is judged beside. `H⁻¹` once; the residual refitted after
// each event is taken out.
struct Base {
  const Design& d;
  Eigen::MatrixXd Hinv;
  Eigen::VectorXd e;  // r − X·θ

  Base(const Design& design, const Eigen::VectorXd& prior) : d(design) {
    Eigen::MatrixXd H = d.columns.transpose() * d.columns;
    H.diagonal() += prior;
    Hinv = H.ldlt().solve(Eigen::MatrixXd::Identity(H.rows(), H.cols()));
    Refit();
  }
  void Refit() { e = d.residual - d.columns * (Hinv * (d.columns.transpose() * d.residual)); }
};

// Running sums over the samples before an instant, for every signature
// at once: the step's columns Z (rows before the instant) as ZᵀX, ZᵀZ and
// Zᵀe, the legs' six single columns side by side.
struct PrefixSums {
  Eigen::MatrixXd XtL, XtF;  // p × 6: the legs', the frame's
  Vector6 LtL = Vector6::Zero(), Lte = Vector6::Zero();
  Matrix6 FtF = Matrix6::Zero();
  Vector6 Fte = Vector6::Zero();

  explicit PrefixSums(Eigen::Index p) : XtL(Eigen::MatrixXd::Zero(p, 6)), XtF(Eigen::MatrixXd::Zero(p, 6)) {}

  void Add(const Base& b, int k) {
    const auto X = b.d.columns.middleRows(3 * k, 3);
    const auto F = b.d.columns.block(3 * k, b.d.frame.begin, 3, 6);
    const Eigen::Matrix<double, 3, 6>& L = b.d.point_per_leg[static_cast<std::size_t>(k)];
    const Vector3 e = b.e.segment<3>(3 * k);
    XtL.noalias() += X.transpose() * L;
    XtF.noalias() += X.transpose() * F;
    LtL += L.colwise().squaredNorm().transpose();
    Lte.noalias() += L.transpose() * e;
    FtF.noalias() += F.transpose() * F;
    Fte.noalias() += F.transpose() * e;
  }

  // The squared error a step of each signature at this instant removes
  // (0: not estimable there).
  std::array<double, kSignatures> Gains(const Base& b) const {
    std::array<double, kSignatures> gains{};
    const Eigen::MatrixXd HL = b.Hinv * XtL;
    for (int j = 0; j < kLegSignatures; ++j) {
      const double projected = LtL(j) - XtL.col(j).dot(HL.col(j));
      if (projected > 1e-9 * LtL(j)) gains[static_cast<std::size_t>(j)] = Lte(j) * Lte(j) / projected;
    }
    const Matrix6 projected = FtF - XtF.transpose() * (b.Hinv * XtF);
    if ((projected.diagonal().array() > 1e-9 * FtF.diagonal().array()).all()) {
      const Eigen::LLT<Matrix6> llt(projected);
      if (llt.info() == Eigen::Success) gains[kLegSignatures] = Fte.dot(llt.solve(Fte));
    }
    return gains;
  }
};

// Samples in time order, the blocks the noise is read over and the candidate instants.
struct Timeline {
  std::vector<int> order;       // samples by time
  std::vector<int> block;       // of each position in `order`
  std::vector<char> candidate;  // a step may start at this position
  std::vector<int> grid;        // the positions the coarse scan evaluates
  int blocks = 0;

  Timeline(const Design& d, const ChangePointOptions& o) {
    const int n = d.samples();
    order.resize(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return d.time_s[static_cast<std::size_t>(a)] < d.time_s[static_cast<std::size_t>(b)];
    });
    block.resize(order.size());
    candidate.assign(order.size(), 0);
    const int side = std::max(kMinSideSamples, static_cast<int>(std::ceil(o.min_side_share * n)));
    double block_start = 0.0, next_grid = -1e300;
    for (int pos = 0; pos < n; ++pos) {
      const std::size_t k = static_cast<std::size_t>(order[static_cast<std::size_t>(pos)]);
      const double t = d.time_s[k];
      const bool new_run = pos > 0 && d.sample_run[k] != d.sample_run[static_cast<std::size_t>(order[pos - 1])];
      if (pos == 0 || new_run || t - block_start >= o.block_s) ++blocks, block_start = t;
      block[static_cast<std::size_t>(pos)] = blocks - 1;
      const bool later = pos > 0 && t > d.time_s[static_cast<std::size_t>(order[pos - 1])];
      if (pos >= side && pos <= n - side && later) {
        candidate[static_cast<std::size_t>(pos)] = 1;
        if (t >= next_grid) grid.push_back(pos), next_grid = t + o.grid_s;
      }
    }
  }
  int at(int pos) const { return order[static_cast<std::size_t>(pos)]; }
};

struct Best {
  int pos = -1;
  double gain = 0.0;
};

// The instant of each signature whose step removes the most: on the grid,
// then at every sample between the grid's neighbours of the best.
std::vector<Best> Scan(const Base& b, const Timeline& line, int* candidates) {
  std::vector<Best> best(kSignatures);
  const int n = static_cast<int>(line.order.size());
  {
    PrefixSums sums(b.d.columns.cols());
    std::size_t g = 0;
    for (int pos = 0; pos < n; ++pos) {
      if (g < line.grid.size() && line.grid[g] == pos) {
        const std::array<double, kSignatures> gains = sums.Gains(b);
        for (std::size_t s = 0; s < gains.size(); ++s) {
          if (gains[s] > best[s].gain) best[s] = {pos, gains[s]};
        }
        ++g;
      }
      sums.Add(b, line.at(pos));
    }
  }
  *candidates = static_cast<int>(std::count(line.candidate.begin(), line.candidate.end(), 1));
  std::vector<std::pair<int, int>> window(kSignatures, {n, -1});
  for (int s = 0; s < kSignatures; ++s) {
    const int pos = best[static_cast<std::size_t>(s)].pos;
    if (pos < 0) continue;
    const auto it = std::lower_bound(line.grid.begin(), line.grid.end(), pos);
    window[static_cast<std::size_t>(s)] = {it == line.grid.begin() ? pos : *(it - 1),
                                           it + 1 == line.grid.end() ? n - 1 : *(it + 1)};
  }
  PrefixSums sums(b.d.columns.cols());
  for (int pos = 0; pos < n; ++pos) {
    const auto inside = [&](const std::pair<int, int>& w) { return pos >= w.first && pos <= w.second; };
    if (line.candidate[static_cast<std::size_t>(pos)] && std::any_of(window.begin(), window.end(), inside)) {
      const std::array<double, kSignatures> gains = sums.Gains(b);
      for (std::size_t s = 0; s < gains.size(); ++s) {
        if (inside(window[s]) && gains[s] > best[s].gain) best[s] = {pos, gains[s]};
      }
    }
    sums.Add(b, line.at(pos));
  }
  return best;
}

// A step's (or a drift's) columns, fitted beside the base: the amplitude,
// the squared error it removes and, for a step, its σ.
struct Fitted {
  Eigen::MatrixXd Z;  // 3 rows per sample
  Eigen::VectorXd a;
  Eigen::MatrixXd covariance;  // white noise's, widened by the signature's inflation
  Eigen::VectorXd rest;        // the residual after it
  double gain = 0.0, sigma2 = 0.0, inflation = 1.0, wald = 0.0;
};

Fitted FitBeside(const Base& b, Eigen::MatrixXd Z) {
  Fitted f;
  f.Z = std::move(Z);
  const Eigen::MatrixXd projected = f.Z - b.d.columns * (b.Hinv * (b.d.columns.transpose() * f.Z));
  const Eigen::MatrixXd G = projected.transpose() * projected;
  const Eigen::VectorXd g = projected.transpose() * b.e;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(G);
  f.a = ldlt.solve(g);
  f.gain = std::max(0.0, g.dot(f.a));
  return f;
}

// How much wider than white noise's the σ of a fit along `signature` is,
// read off the residual `rest` itself: over parts of the session, the
// squared sums of Cᵀr against the sums of its squares (1 for white noise;
// a misfit correlated over a while adds up within a part). The parts are
// the blocks (seconds: a misfit following the motion) and the runs (a
// misfit that sets runs apart, as an unmodelled sway's quasi-static part
// does), and the wider reading counts. One figure per signature for the
// whole session, whatever the candidate instant, so that a step on a short
// side of the session is judged by the whole session's noise.
double Inflation(const Design& d, const Timeline& line, int signature, const Eigen::VectorXd& rest) {
  Eigen::VectorXd block_sum = Eigen::VectorXd::Zero(Width(signature));
  std::vector<Eigen::VectorXd> run_sums(d.runs.size(), Eigen::VectorXd::Zero(Width(signature)));
  double blocks = 0.0, white = 0.0;
  int current = -1;
  for (std::size_t pos = 0; pos <= line.order.size(); ++pos) {
    if (pos == line.order.size() || line.block[pos] != current) {
      blocks += block_sum.squaredNorm();
      block_sum.setZero();
      if (pos == line.order.size()) break;
      current = line.block[pos];
    }
    const int k = line.order[pos];
    const Eigen::VectorXd c = SignatureAt(d, signature, k).transpose() * rest.segment<3>(3 * k);
    block_sum += c;
    run_sums[static_cast<std::size_t>(d.sample_run[static_cast<std::size_t>(k)])] += c;
    white += c.squaredNorm();
  }
  double runs = 0.0;
  for (const Eigen::VectorXd& sum : run_sums) runs += sum.squaredNorm();
  return white > 0.0 ? std::max({1.0, blocks / white, runs / white}) : 1.0;
}

// The step judged: its σ and statistic with the noise as the residual
// after it shows it (white noise's σ², widened by the signature's inflation).
void Judge(const Base& b, const Timeline& line, int signature, Fitted* f) {
  const Eigen::Index K = f->Z.cols();
  const Eigen::MatrixXd projected = f->Z - b.d.columns * (b.Hinv * (b.d.columns.transpose() * f->Z));
  f->rest = b.e - projected * f->a;
  const double dof = std::max(1.0, static_cast<double>(b.e.size() - b.d.columns.cols() - K));
  f->sigma2 = f->rest.squaredNorm() / dof;
  f->inflation = Inflation(b.d, line, signature, f->rest);
  const Eigen::MatrixXd bread = (projected.transpose() * projected).ldlt().solve(Eigen::MatrixXd::Identity(K, K));
  f->covariance = f->sigma2 * f->inflation * bread;
  f->wald = f->gain / (f->sigma2 * f->inflation);
}

// Whether one step is all the signature holds: what is left along it after
// the step, fitted block by block (a level per block, in the directions the
// block's motion lets the signature show), against white noise's χ² at 1%.
// A rig that changed once is one rig on each side; a misfit that varies
// from block to block (a sway the model lacks, runs that sit apart) is
// structure, and a step fitted into it is no event. Returns what is left
// and its bar, in σ².
std::pair<double, double> LeftBlockByBlock(const Design& d, const Timeline& line, int signature, const Fitted& f) {
  const Eigen::Index K = Width(signature);
  double left = 0.0;
  int dof = 0;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(K);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(K, K);
  int current = -1;
  for (std::size_t pos = 0; pos <= line.order.size(); ++pos) {
    if (pos == line.order.size() || line.block[pos] != current) {
      if (current >= 0) {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
        const double floor = 1e-6 * std::max(eig.eigenvalues().maxCoeff(), 1e-300);
        const Eigen::VectorXd along = eig.eigenvectors().transpose() * g;
        for (Eigen::Index j = 0; j < K; ++j) {
          if (eig.eigenvalues()(j) <= floor) continue;
          left += along(j) * along(j) / eig.eigenvalues()(j);
          ++dof;
        }
      }
      g.setZero();
      M.setZero();
      if (pos == line.order.size()) break;
      current = line.block[pos];
    }
    const int k = line.order[pos];
    const Eigen::MatrixXd C = SignatureAt(d, signature, k);
    g.noalias() += C.transpose() * f.rest.segment<3>(3 * k);
    M.noalias() += C.transpose() * C;
  }
  const double bar = boost::math::quantile(boost::math::complement(boost::math::chi_squared(std::max(1, dof)), 0.01));
  return {left / f.sigma2, bar};
}

// The bar a step's statistic must pass: χ² of its columns at the
// false-alarm rate shared over every candidate instant of the scan's grid
// and every signature (Bonferroni; neighbouring instants are nearly the
// same test, so this errs on the side of no event).
double Threshold(int width, int grid, const ChangePointOptions& o) {
  const double share = o.false_alarm / (std::max(1, grid) * kSignatures);
  return boost::math::quantile(boost::math::complement(boost::math::chi_squared(width), share));
}

// The rows before `pos` (in time) of `signature`: a step there.
Eigen::MatrixXd StepColumns(const Design& d, const Timeline& line, int signature, int pos) {
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(3 * d.samples(), Width(signature));
  for (int q = 0; q < pos; ++q) {
    const int k = line.at(q);
    Z.middleRows(3 * k, 3) = SignatureAt(d, signature, k);
  }
  return Z;
}

// The signature times a profile in time: a drift of it.
Eigen::MatrixXd DriftColumns(const Design& d, int signature, const std::function<double(double)>& profile) {
  Eigen::MatrixXd Z(3 * d.samples(), Width(signature));
  for (int k = 0; k < d.samples(); ++k) {
    Z.middleRows(3 * k, 3) = SignatureAt(d, signature, k) * profile(d.time_s[static_cast<std::size_t>(k)]);
  }
  return Z;
}

// The best drift of the signature beside the base: its name and the squared error it removes.
std::pair<std::string, double> BestDrift(const Base& b, int signature, const ChangePointOptions& o) {
  const auto [lo, hi] = std::minmax_element(b.d.time_s.begin(), b.d.time_s.end());
  const double t0 = *lo, span = std::max(*hi - *lo, 1e-9);
  std::pair<std::string, double> best{
      "linear", FitBeside(b, DriftColumns(b.d, signature, [&](double t) { return (t - t0) / span; })).gain};
  for (double tau : o.drift_time_constants_s) {
    const double gain =
        FitBeside(b, DriftColumns(b.d, signature, [&](double t) { return 1.0 - std::exp(-(t - t0) / tau); })).gain;
    if (gain > best.second) best = {fmt::format("tau_{:g}s", tau), gain};
  }
  return best;
}

ChangeEvent EventOf(const Design& d, const Timeline& line, int signature, int pos, const Fitted& f, double threshold) {
  ChangeEvent ev;
  ev.kind = signature < kLegSignatures ? ChangeKind::kLegLength : ChangeKind::kTrackerFrame;
  ev.leg = signature < kLegSignatures ? signature : -1;
  const std::size_t after = static_cast<std::size_t>(line.at(pos)), before = static_cast<std::size_t>(line.at(pos - 1));
  ev.time_s = d.time_s[after];
  ev.after_s = d.time_s[before];
  ev.run = d.runs[static_cast<std::size_t>(d.sample_run[after])];
  // The step's columns sit before the instant: the rig after it differs by −a.
  ev.size = -f.a;
  ev.sigma = f.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  ev.wald = f.wald;
  ev.threshold = threshold;
  ev.inflation = f.inflation;
  return ev;
}

inline constexpr double kLargestSigma = 1e-3;  // m or rad

// Whether the step's statistic (in the widened σ²) is step_over_structure
// times what is left along its signature block by block (`left_sigma2`,
// in white noise's σ²): one change standing on structure, not fitted into
// it. The more the signature holds block by block, and the more its noise
// adds up over a block, the larger the step must be.
bool StandsAboveStructure(const Fitted& step, double left_sigma2, const ChangePointOptions& o) {
  return step.wald >= o.step_over_structure * left_sigma2;
}

// The step of `signature` at `pos` judged against the noise and the
// structure (Judge, LeftBlockByBlock): nothing when it is within the
// noise; an event whose `alternative` is kStructure when what is left
// along its signature is more than one step.
std::optional<ChangeEvent> Assess(const Base& base, const Timeline& line, int signature, int pos,
                                  const ChangePointOptions& o, Fitted* step) {
  const double threshold = Threshold(Width(signature), static_cast<int>(line.grid.size()), o);
  Judge(base, line, signature, step);
  if (!(step->wald >= threshold)) return std::nullopt;
  ChangeEvent ev = EventOf(base.d, line, signature, pos, *step, threshold);
  ev.step_sigma2 = step->wald;
  std::tie(ev.left_sigma2, ev.left_threshold) = LeftBlockByBlock(base.d, line, signature, *step);
  if (ev.left_sigma2 > ev.left_threshold && !StandsAboveStructure(*step, ev.left_sigma2, o))
    ev.alternative = StepRejection::kStructure;
  // A step the session cannot size to within a millimetre or a milliradian
  // in some direction (its columns all but collinear with the rest there)
  // passes its bar on the directions it can size, but is no change a rig
  // engineer could look for.
  if (!(ev.sigma.maxCoeff() <= kLargestSigma)) ev.alternative = StepRejection::kUndetermined;
  return ev;
}

// The step against the best drift of its signature (BestDrift), in the
// step's σ²: `alternative` kDrift when the step does not beat it by
// step_over_drift.
void AgainstADrift(const Base& base, int signature, const Fitted& step, const ChangePointOptions& o, ChangeEvent* ev) {
  const auto [drift, drift_gain] = BestDrift(base, signature, o);
  ev->drift = drift;
  ev->drift_sigma2 = drift_gain / (step.sigma2 * step.inflation);
  if (ev->step_sigma2 - ev->drift_sigma2 < o.step_over_drift) ev->alternative = StepRejection::kDrift;
}

// Whether a better step of another signature, already turned away, stands
// at the step's instant: the same change seen through a signature that
// mimics part of it (a knocked tracker through a leg whose pose the motion
// before it barely varied), which must not be reported in its place.
// A shadow turned away casts none of its own: the chain would reach past
// shadow_s.
bool BesideABetterStep(const ChangeEvent& step, const std::vector<ChangeEvent>& better, const ChangePointOptions& o) {
  return std::any_of(better.begin(), better.end(), [&](const ChangeEvent& b) {
    return b.alternative != StepRejection::kOtherSignature && std::abs(b.time_s - step.time_s) <= o.shadow_s;
  });
}

// Each row of the data the design's samples came from, moved by `shift` (3 per sample, tracker frame).
MeasurementData Shifted(const MeasurementData& data, const Design& d, const Eigen::VectorXd& shift) {
  MeasurementData out = data;
  for (int k = 0; k < d.samples(); ++k) {
    out.rows[static_cast<std::size_t>(d.source_row[static_cast<std::size_t>(k)])].point_m -= shift.segment<3>(3 * k);
  }
  return out;
}

// A significant step of one signature at the scan's best instant, judged (Assess).
struct Candidate {
  ChangeEvent ev;
  Fitted step;
  int signature = 0;
};

// Whether `a` explains the data better than `b`, the parameters' count
// counted (BIC, in the larger of the two widened σ²: a correlated misfit
// gives each column more than white noise would): of two steps at one
// instant, the one with fewer columns unless the other removes
// ln(residual rows) σ² more per column it adds; of two of as many columns,
// `b` unless `a` removes step_over_drift σ² more.
bool ExplainsBetter(const Candidate& a, const Candidate& b, Eigen::Index rows, const ChangePointOptions& o) {
  const double sigma2 = std::max(a.step.sigma2 * a.step.inflation, b.step.sigma2 * b.step.inflation);
  const int extra_columns = Width(a.signature) - Width(b.signature);
  const double bar = extra_columns == 0 ? o.step_over_drift : extra_columns * std::log(static_cast<double>(rows));
  return (a.step.gain - b.step.gain) / sigma2 > bar;
}

// The event to take of the candidates, if any: the one past its bar by the
// most (a leg's step must not go to the tracker's frame, whose six columns
// mimic part of it, by their number alone) unless a drift explains it as
// well or a better step of another signature at its instant was turned
// away; then the next. Of accepted steps at one instant, the one that
// explains the data better (ExplainsBetter) is taken: a signature whose
// noise the model's misfit widens stands lower past its bar than its
// shadow. The candidates turned away go to `rejected` when none is taken.
std::optional<std::size_t> ChooseEvent(const Base& base, const ChangePointOptions& o,
                                       std::vector<Candidate>* candidates, std::vector<ChangeEvent>* rejected) {
  std::vector<Candidate>& c = *candidates;
  std::vector<std::size_t> order(c.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return c[a].ev.wald - c[a].ev.threshold > c[b].ev.wald - c[b].ev.threshold;
  });
  const auto accepted = [&](Candidate& x) {
    if (x.ev.alternative == StepRejection::kNone && BesideABetterStep(x.ev, *rejected, o))
      x.ev.alternative = StepRejection::kOtherSignature;
    if (x.ev.alternative == StepRejection::kNone) AgainstADrift(base, x.signature, x.step, o, &x.ev);
    return x.ev.alternative == StepRejection::kNone;
  };
  for (std::size_t n = 0; n < order.size(); ++n) {
    const std::size_t first = order[n];
    if (!accepted(c[first])) {
      rejected->push_back(c[first].ev);
      continue;
    }
    std::size_t k = first;
    for (std::size_t m = n + 1; m < order.size(); ++m) {
      Candidate& other = c[order[m]];
      if (std::abs(other.ev.time_s - c[first].ev.time_s) > o.shadow_s) continue;
      if (ExplainsBetter(other, c[k], base.e.size(), o) && accepted(other)) k = order[m];
    }
    return k;
  }
  return std::nullopt;
}

}  // namespace

const char* ChangeKindName(ChangeKind kind) { return kind == ChangeKind::kLegLength ? "leg_length" : "tracker_frame"; }

std::string DescribeEvent(const ChangeEvent& e) {
  const std::string when = fmt::format("at {:.2f} s (run {})", e.time_s, e.run);
  if (e.kind == ChangeKind::kLegLength) {
    return fmt::format("{}, leg {} became {:.1f} µm ± {:.1f} {}", when, e.leg + 1, std::abs(e.size(0)) * 1e6,
                       e.sigma(0) * 1e6, e.size(0) >= 0.0 ? "longer" : "shorter");
  }
  const Vector3 t = e.size.head<3>(), w = e.size.tail<3>();
  return fmt::format(
      "{}, the tracker's frame moved by ({:.1f}, {:.1f}, {:.1f}) µm and turned by ({:.1f}, {:.1f}, "
      "{:.1f}) µrad (σ {:.1f} µm, {:.1f} µrad)",
      when, t.x() * 1e6, t.y() * 1e6, t.z() * 1e6, w.x() * 1e6, w.y() * 1e6, w.z() * 1e6,
      e.sigma.head<3>().maxCoeff() * 1e6, e.sigma.tail<3>().maxCoeff() * 1e6);
}

ChangeSearch FindChanges(const PlatformModel& model, const MeasurementData& data, const DesignOptions& design,
                         const ChangePointOptions& o, MeasurementData* corrected) {
  const auto start = std::chrono::steady_clock::now();
  ChangeSearch search;
  *corrected = data;
  if (!o.search || data.rows.empty()) return search;
  Design d = BuildDesign(model, data, design);
  const Eigen::VectorXd prior = PriorWeights(d, PriorVariance(d, NoiseFloorRms(d)));
  const TimeOffset clock = EstimateTimeOffset(d, prior);
  if (clock.applied) RemoveTimeOffset(clock.offset_s, &d);
  const Timeline line(d, o);
  search.searched = true;
  search.blocks = line.blocks;
  if (line.grid.empty()) return search;
  Base base(d, prior);
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(d.residual.size());
  while (static_cast<int>(search.events.size()) < o.max_events) {
    const std::vector<Best> best = Scan(base, line, &search.candidates);
    std::vector<Candidate> candidates;
    for (int s = 0; s < kSignatures; ++s) {
      const int pos = best[static_cast<std::size_t>(s)].pos;
      if (pos <= 0) continue;
      Fitted step = FitBeside(base, StepColumns(d, line, s, pos));
      if (std::optional<ChangeEvent> ev = Assess(base, line, s, pos, o, &step))
        candidates.push_back({std::move(*ev), std::move(step), s});
    }
    std::vector<ChangeEvent> rejected;
    const std::optional<std::size_t> k = ChooseEvent(base, o, &candidates, &rejected);
    if (!k) {
      search.rejected = std::move(rejected);
      break;
    }
    const Candidate& chosen = candidates[*k];
    const Eigen::VectorXd moved = chosen.step.Z * chosen.step.a;
    d.residual -= moved;
    shift += moved;
    base.Refit();
    search.events.push_back(chosen.ev);
  }
  if (!search.events.empty()) *corrected = Shifted(data, d, shift);
  search.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return search;
}

}  // namespace edsp::gap
