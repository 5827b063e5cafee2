#include "edsp/diagnosis/residual_structure.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>

#include <Eigen/QR>
#include <boost/math/distributions/chi_squared.hpp>
#include <fmt/format.h>
#include <unsupported/Eigen/FFT>

namespace edsp::gap {

namespace {

constexpr double kBandHz = 0.05;  // the pooled spectrum's resolution
constexpr double kDriftHz = 0.2;  // below: drift, not a mode
constexpr double kPeakOverMedian = 8.0;
constexpr double kRunsApartLevel = 0.999;  // χ² quantile the runs' means must exceed

// One run's samples on one axis, mean removed.
struct Series {
  std::vector<double> values;
  double dt_s = 0.0;
  double variance = 0.0;
};

// The mean step, not the median: a tracker stamped on a controller's tick
// alternates between two steps, and the median would pick one. Without the
// holes (steps over 3× the median: rows the data flagged timing_event, a
// beam break), which would lower every frequency found by their share.
double MeanStep(const Design& d, const ColumnRange& run) {
  std::vector<double> steps;
  for (int k = run.begin + 1; k < run.begin + run.count; ++k) {
    steps.push_back(d.time_s[static_cast<std::size_t>(k)] - d.time_s[static_cast<std::size_t>(k - 1)]);
  }
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  double sum = 0.0;
  int n = 0;
  for (double s : steps) {
    if (s <= 3.0 * median) sum += s, ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

std::vector<Series> SeriesOf(const Design& d, const Eigen::VectorXd& residual) {
  std::vector<Series> all;
  for (const ColumnRange& run : d.run_samples) {
    if (run.count < 64) continue;
    const double dt = MeanStep(d, run);
    if (!(dt > 0.0)) continue;
    for (int axis = 0; axis < 3; ++axis) {
      Series s;
      s.dt_s = dt;
      double mean = 0.0;
      for (int k = run.begin; k < run.begin + run.count; ++k) s.values.push_back(residual(3 * k + axis));
      for (double v : s.values) mean += v;
      mean /= static_cast<double>(s.values.size());
      for (double& v : s.values) v -= mean, s.variance += v * v;
      s.variance /= static_cast<double>(s.values.size());
      all.push_back(std::move(s));
    }
  }
  return all;
}

// Periodogram |X_j|² of bins j = 1 … N/2.
std::vector<double> Periodogram(const std::vector<double>& values) {
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, values);
  std::vector<double> power;
  for (std::size_t j = 1; j <= values.size() / 2; ++j) power.push_back(std::norm(spectrum[j]));
  return power;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Share of a series' variance above its white level: white noise has an
// exponentially distributed periodogram whose median is ln 2 × its mean.
double ShareAboveWhite(const std::vector<double>& power) {
  double total = 0.0;
  for (double p : power) total += p;
  if (total <= 0.0) return 0.0;
  const double white_mean = Median(power) / std::log(2.0);
  return std::clamp(1.0 - white_mean * static_cast<double>(power.size()) / total, 0.0, 1.0);
}

// The same pooled over series, weighted by their variance.
double ShareAboveWhite(const std::vector<Series>& series) {
  double above = 0.0, total = 0.0;
  for (const Series& s : series) {
    above += ShareAboveWhite(Periodogram(s.values)) * s.variance;
    total += s.variance;
  }
  return total > 0.0 ? above / total : 0.0;
}

// Peak of the pooled spectrum (each series normalised to its variance) above
// the drift band, its damping from the half-power width.
void FindPeak(const std::vector<Series>& series, ResidualStructure* out) {
  std::map<int, double> bands;
  double nyquist = 1e9;
  for (const Series& s : series) {
    const std::vector<double> power = Periodogram(s.values);
    double total = 0.0;
    for (double p : power) total += p;
    if (total <= 0.0) continue;
    const double n = static_cast<double>(s.values.size());
    nyquist = std::min(nyquist, 0.5 / s.dt_s);
    for (std::size_t j = 0; j < power.size(); ++j) {
      const double hz = static_cast<double>(j + 1) / (n * s.dt_s);
      bands[static_cast<int>(hz / kBandHz)] += power[j] / total;
    }
  }
  std::vector<double> levels;
  int peak = -1;
  for (const auto& [band, level] : bands) {
    if (band * kBandHz < kDriftHz || band * kBandHz > nyquist) continue;
    levels.push_back(level);
    if (peak < 0 || level > bands[peak]) peak = band;
  }
  if (peak < 0 || bands[peak] < kPeakOverMedian * Median(levels)) return;
  out->dominant_hz = (peak + 0.5) * kBandHz;
  const double half = 0.5 * bands[peak];
  int lo = peak, hi = peak;
  while (bands.count(lo - 1) && bands[lo - 1] >= half) --lo;
  while (bands.count(hi + 1) && bands[hi + 1] >= half) ++hi;
  if (hi - lo >= 2) out->damping = (hi - lo + 1) * kBandHz / (2.0 * out->dominant_hz);
}

// The runs' means against the scatter white noise gives them. Each run's
// mean on each axis has variance σ²·(1 + ρ)/(1 − ρ)/n under the run's own
// scatter σ² and lag-1 autocorrelation ρ (a structured run holds fewer
// independent samples); the global frame takes up one mean per axis. Returns
// the share of the residual's variance in the means beyond that scatter,
// 0 unless the sum of their squared z-scores exceeds χ² at `level`.
// `frame_fitted`: the residual's own frame was fitted on these runs (in
// sample), which takes up one mean per axis; held out, it was not.
double RunOffsetShare(const Design& d, const Eigen::VectorXd& residual, double level, bool frame_fitted) {
  double chi2 = 0.0, excess = 0.0;
  int dof = frame_fitted ? -3 : 0;
  for (const ColumnRange& run : d.run_samples) {
    if (run.count < 16) continue;
    for (int axis = 0; axis < 3; ++axis) {
      double mean = 0.0;
      for (int k = run.begin; k < run.begin + run.count; ++k) mean += residual(3 * k + axis);
      mean /= run.count;
      double var = 0.0, lag1 = 0.0;
      for (int k = run.begin; k < run.begin + run.count; ++k) {
        const double v = residual(3 * k + axis) - mean;
        var += v * v;
        if (k > run.begin) lag1 += v * (residual(3 * (k - 1) + axis) - mean);
      }
      if (!(var > 0.0)) continue;
      const double rho = std::clamp(lag1 / var, 0.0, 0.99);
      const double mean_var = var / run.count * (1.0 + rho) / (1.0 - rho) / run.count;
      chi2 += mean * mean / mean_var;
      excess += run.count * std::max(0.0, mean * mean - mean_var);
      ++dof;
    }
  }
  const double total = residual.squaredNorm();
  if (dof < 1 || !(total > 0.0)) return 0.0;
  const boost::math::chi_squared chi(dof);
  if (chi2 <= boost::math::quantile(chi, level)) return 0.0;
  return std::clamp(excess / total, 0.0, 1.0);
}

// Per-sample drivers the structure may follow, from the model's point A.
struct Drivers {
  std::map<std::string, std::vector<Eigen::VectorXd>> features;  // per driver, per sample
};

Drivers DriversOf(const Design& d) {
  Drivers drivers;
  const int n = d.samples();
  for (const char* name : {"acceleration", "velocity", "direction", "pose", "time"}) {
    drivers.features[name].assign(static_cast<std::size_t>(n), Eigen::VectorXd());
  }
  for (const ColumnRange& run : d.run_samples) {
    for (int k = run.begin; k < run.begin + run.count; ++k) {
      const int a = std::max(run.begin, k - 1), b = std::min(run.begin + run.count - 1, k + 1);
      const std::size_t s = static_cast<std::size_t>(k);
      const auto point = [&](int i) { return d.model_point[static_cast<std::size_t>(i)]; };
      const auto time = [&](int i) { return d.time_s[static_cast<std::size_t>(i)]; };
      Vector3 velocity = Vector3::Zero(), accel = Vector3::Zero();
      if (b > a && time(b) > time(a)) velocity = (point(b) - point(a)) / (time(b) - time(a));
      if (a < k && k < b && time(b) > time(a)) {
        accel = 4.0 * (point(b) - 2.0 * point(k) + point(a)) / ((time(b) - time(a)) * (time(b) - time(a)));
      }
      const Vector3 direction =
          velocity.unaryExpr([](double v) { return std::abs(v) < 1e-4 ? 0.0 : (v > 0 ? 1.0 : -1.0); });
      const Vector3 pose = point(k) - d.model_point.front();
      drivers.features["acceleration"][s] = accel;
      drivers.features["velocity"][s] = velocity;
      drivers.features["direction"][s] = direction;
      Eigen::VectorXd p(6);
      p << pose, pose.cwiseAbs2();
      drivers.features["pose"][s] = p;
      Eigen::VectorXd t(2);
      t << time(k), time(k) * time(k);
      drivers.features["time"][s] = t;
    }
  }
  return drivers;
}

// Share of the residual's variance a linear fit on the driver (per axis,
// with an intercept per run) explains.
double ExplainedBy(const Design& d, const Eigen::VectorXd& residual, const std::vector<Eigen::VectorXd>& feature) {
  const int n = d.samples(), runs = static_cast<int>(d.run_samples.size());
  const int width = static_cast<int>(feature.front().size());
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, width + runs);
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd f = feature[static_cast<std::size_t>(k)];
    X.row(k).head(width) = f.transpose();
    X(k, width + d.sample_run[static_cast<std::size_t>(k)]) = 1.0;
  }
  // Scale columns so time² and millimetre poses condition alike.
  const Eigen::VectorXd scale = X.colwise().norm().transpose().cwiseMax(1e-300).cwiseInverse();
  const Eigen::MatrixXd Xs = X * scale.asDiagonal();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xs);
  double sse = 0.0, sst = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::VectorXd y(n);
    for (int k = 0; k < n; ++k) y(k) = residual(3 * k + axis);
    Eigen::VectorXd centred = y;
    for (const ColumnRange& run : d.run_samples) {
      centred.segment(run.begin, run.count).array() -= y.segment(run.begin, run.count).mean();
    }
    sst += centred.squaredNorm();
    sse += (y - Xs * qr.solve(y)).squaredNorm();
  }
  return sst > 0.0 ? std::clamp(1.0 - sse / sst, 0.0, 1.0) : 0.0;
}

std::vector<std::string> LargestRuns(const Design& d, const Eigen::VectorXd& residual) {
  std::vector<std::pair<double, std::string>> rms;
  for (std::size_t r = 0; r < d.run_samples.size(); ++r) {
    const ColumnRange& run = d.run_samples[r];
    if (run.count == 0) continue;
    rms.emplace_back(std::sqrt(residual.segment(3 * run.begin, 3 * run.count).squaredNorm() / run.count), d.runs[r]);
  }
  std::sort(rms.rbegin(), rms.rend());
  std::vector<std::string> names;
  for (std::size_t k = 0; k < rms.size() && k < 2; ++k) names.push_back(rms[k].second);
  return names;
}

}  // namespace

ResidualStructure AnalyseStructure(const Design& d, const Eigen::VectorXd& in_sample, const Eigen::VectorXd& residual,
                                   const StructureOptions& o) {
  ResidualStructure out;
  out.whiteness = TestWhiteness(d, residual);
  out.in_sample_whiteness = TestWhiteness(d, in_sample);
  const std::vector<Series> series = SeriesOf(d, residual);
  out.structured_share = ShareAboveWhite(series);
  out.in_sample_share = ShareAboveWhite(SeriesOf(d, in_sample));
  out.run_offset_share = RunOffsetShare(d, residual, kRunsApartLevel, false);
  out.in_sample_run_offset_share = RunOffsetShare(d, in_sample, kRunsApartLevel, true);
  out.runs_apart =
      out.run_offset_share >= o.min_run_offset_share && out.in_sample_run_offset_share >= o.min_run_offset_share;
  const bool within_runs = !out.whiteness.white && out.structured_share >= o.min_share &&
                           !out.in_sample_whiteness.white && out.in_sample_share >= o.min_share;
  out.structured = within_runs || out.runs_apart;
  // The within-run share is of the variance about each run's mean; with the
  // runs apart, their means' share is structure too.
  if (out.runs_apart) out.structured_share = out.run_offset_share + (1.0 - out.run_offset_share) * out.structured_share;
  const double mean_square = d.samples() > 0 ? residual.squaredNorm() / d.samples() : 0.0;
  out.structured_rms_m = std::sqrt(out.structured_share * mean_square);
  FindPeak(series, &out);
  const Drivers drivers = DriversOf(d);
  for (const auto& [name, feature] : drivers.features) {
    if (feature.empty()) continue;
    const double r2 = ExplainedBy(d, residual, feature);
    if (r2 > out.follows_r2) out.follows_r2 = r2, out.follows = name;
  }
  if (out.follows_r2 < o.min_driver_r2) out.follows = "nothing";
  out.largest_in = LargestRuns(d, residual);
  return out;
}

std::string ResidualStructure::Describe() const {
  std::string text = fmt::format(
      "{:.0f}% of the held-out residual's variance ({:.1f} µm RMS) is structure above the white level "
      "(Ljung-Box Q {:.0f} against {:.0f}, lag-1 autocorrelation {:.2f})",
      100 * structured_share, structured_rms_m * 1e6, whiteness.q, whiteness.threshold, whiteness.lag1);
  if (runs_apart) {
    text += fmt::format(
        "; the runs sit apart ({:.0f}% of the variance in their means, beyond the noise's "
        "scatter: a tracker stand or a mount that moved between them?)",
        100 * run_offset_share);
  }
  if (dominant_hz > 0.0) {
    text += damping > 0.0 ? fmt::format("; a spectral peak at {:.2f} Hz, damping ≈ {:.3f}", dominant_hz, damping)
                          : fmt::format("; a spectral peak at {:.2f} Hz", dominant_hz);
  }
  text += follows == "nothing" ? std::string("; it follows none of acceleration, velocity, direction, pose, time")
                               : fmt::format("; it follows {} (explains {:.0f}%)", follows, 100 * follows_r2);
  if (!largest_in.empty()) text += fmt::format("; largest in {}", fmt::join(largest_in, ", "));
  return text;
}

}  // namespace edsp::gap
