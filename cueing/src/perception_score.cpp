#include "edsp/cueing/perception_score.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {
namespace {

double Rms(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

// Pearson's correlation of a[k] with b[k + lag] over their overlap.
double Correlation(const std::vector<double>& a, const std::vector<double>& b, std::size_t lag) {
  const std::size_t n = a.size() - lag;
  double mean_a = 0.0, mean_b = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    mean_a += a[k];
    mean_b += b[k + lag];
  }
  mean_a /= static_cast<double>(n);
  mean_b /= static_cast<double>(n);
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double da = a[k] - mean_a, db = b[k + lag] - mean_b;
    ab += da * db;
    aa += da * da;
    bb += db * db;
  }
  // A constant signal carries no shape to correlate (a channel neither moves).
  constexpr double kFlat = 1e-24;
  return aa > kFlat && bb > kFlat ? ab / std::sqrt(aa * bb) : 0.0;
}

}  // namespace

PerceptionScore ScorePerception(const VestibularParameters& parameters, const VehicleSeries& vehicle,
                                const VehicleSeries& platform, double max_delay_s) {
  if (vehicle.samples.size() != platform.samples.size() || vehicle.samples.size() < 2) {
    throw std::invalid_argument(fmt::format("perception score: the vehicle has {} samples and the platform {}",
                                            vehicle.samples.size(), platform.samples.size()));
  }
  if (std::fabs(vehicle.period_s - platform.period_s) > 1e-12) {
    throw std::invalid_argument(fmt::format("perception score: the vehicle's period {} s is not the platform's {} s",
                                            vehicle.period_s, platform.period_s));
  }
  const auto felt_in_vehicle = Perceive(parameters, vehicle);
  const auto felt_on_platform = Perceive(parameters, platform);
  const std::size_t max_lag =
      std::min(static_cast<std::size_t>(std::max(0.0, max_delay_s) / vehicle.period_s), vehicle.samples.size() / 2);
  PerceptionScore score;
  double sum_squares = 0.0;
  for (int channel = 0; channel < kCueChannels; ++channel) {
    const auto& a = felt_in_vehicle[static_cast<std::size_t>(channel)];
    const auto& b = felt_on_platform[static_cast<std::size_t>(channel)];
    ChannelScore& s = score.channels[static_cast<std::size_t>(channel)];
    s.rms_error = Rms(a, b);
    s.correlation = Correlation(a, b, 0);
    double best = s.correlation;
    for (std::size_t lag = 1; lag <= max_lag; ++lag) {
      const double c = Correlation(a, b, lag);
      if (c > best) {
        best = c;
        s.delay_s = static_cast<double>(lag) * vehicle.period_s;
      }
    }
    s.in_thresholds = s.rms_error / parameters.Threshold(channel);
    sum_squares += s.in_thresholds * s.in_thresholds;
  }
  score.overall = std::sqrt(sum_squares / kCueChannels);
  return score;
}

}  // namespace edsp
