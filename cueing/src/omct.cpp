#include "edsp/cueing/omct.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/cueing/classical_washout.h"
#include "edsp/cueing/platform_motion.h"

namespace edsp {
namespace {

constexpr int kSettlePeriods = 3;
constexpr double kSettleMin_s = 20.0;  // the translation's washout pole at 0.5 rad/s: 4 time constants
constexpr int kMeasuredPeriods = 2;

// Fourier coefficient of `signal` at ω over its samples from `first` on,
// its mean taken out first: the window is whole periods only to a sample,
// and gravity's 9.8 m/s² on z would leak through that difference into a
// response of milli-g (11% of heave's gain at 1 rad/s).
std::complex<double> AtFrequency(const std::vector<double>& signal, double omega, double period_s, std::size_t first) {
  double mean = 0.0;
  for (std::size_t k = first; k < signal.size(); ++k) mean += signal[k];
  mean /= static_cast<double>(signal.size() - first);
  std::complex<double> sum = 0.0;
  for (std::size_t k = first; k < signal.size(); ++k) {
    sum += (signal[k] - mean) * std::exp(std::complex<double>(0.0, -omega * static_cast<double>(k) * period_s));
  }
  return sum;
}

}  // namespace

double OmctAmplitude(int channel) { return channel < 3 ? 0.1 : 0.02; }

OmctPoint MeasureOmct(const PlatformModel& model, const CueingConfig& config, int channel, double frequency_rad_s,
                      double amplitude) {
  if (channel < 0 || channel >= kCueChannels) throw std::invalid_argument(fmt::format("no cue channel {}", channel));
  if (!(frequency_rad_s > 0.0)) throw std::invalid_argument(fmt::format("OMCT frequency {} rad/s", frequency_rad_s));
  const double period_s = 1.0 / config.rate_hz;
  const double cycle_s = 2.0 * kPi / frequency_rad_s;
  const double settle_s = std::max(kSettlePeriods * cycle_s, std::ceil(kSettleMin_s / cycle_s) * cycle_s);
  const auto samples = static_cast<std::size_t>(std::llround((settle_s + kMeasuredPeriods * cycle_s) / period_s));
  const auto first = static_cast<std::size_t>(std::llround(settle_s / period_s));
  ClassicalWashout washout(config.washout, period_s);
  std::vector<Pose> poses;
  std::vector<double> input;
  poses.reserve(samples);
  input.reserve(samples);
  for (std::size_t k = 0; k < samples; ++k) {
    const double t = static_cast<double>(k) * period_s;
    VehicleSample sample;
    sample.t_s = t;
    const double value = amplitude * std::sin(frequency_rad_s * t);
    if (channel < 3)
      sample.specific_force_m_s2(channel) += value;
    else
      sample.angular_velocity_rad_s(channel - 3) = value;
    input.push_back(value);
    poses.push_back(CueToPlatformPose(model.home_pose(), config.head_in_platform_m, washout.Step(sample)));
  }
  const VehicleSeries felt = PlatformMotionAtHead(poses, period_s, config.head_in_platform_m);
  std::vector<double> output;
  output.reserve(samples);
  for (const VehicleSample& s : felt.samples) output.push_back(ChannelValue(s, channel));
  const std::complex<double> ratio =
      AtFrequency(output, frequency_rad_s, period_s, first) / AtFrequency(input, frequency_rad_s, period_s, first);
  OmctPoint point;
  point.channel = channel;
  point.frequency_rad_s = frequency_rad_s;
  point.gain = std::abs(ratio);
  point.phase_deg = std::arg(ratio) * 180.0 / kPi;
  return point;
}

std::vector<OmctPoint> RunOmct(const PlatformModel& model, const CueingConfig& config) {
  std::vector<OmctPoint> points;
  for (int channel = 0; channel < kCueChannels; ++channel) {
    for (double omega : kOmctFrequencies_rad_s) {
      points.push_back(MeasureOmct(model, config, channel, omega, OmctAmplitude(channel)));
    }
  }
  return points;
}

}  // namespace edsp
