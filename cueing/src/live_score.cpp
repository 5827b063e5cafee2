#include "edsp/cueing/live_score.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/cueing/platform_motion.h"
#include "edsp/kinematics/pose.h"

namespace edsp {
namespace {

constexpr auto kPeriodUs = static_cast<std::int64_t>(kLiveScorePeriod_s * 1e6);

// The vehicle's sample held at each instant of the grid.
VehicleSeries HeldVehicle(const std::vector<HeardVehicleSample>& vehicle, std::int64_t start, std::size_t n) {
  VehicleSeries series;
  series.period_s = kLiveScorePeriod_s;
  series.samples.resize(n);
  std::size_t next = 0;  // the first sample heard after the instant
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t t = start + static_cast<std::int64_t>(k) * kPeriodUs;
    while (next < vehicle.size() && vehicle[next].utime <= t) ++next;
    const HeardVehicleSample& heard = vehicle[std::max<std::size_t>(next, 1) - 1];
    series.samples[k].t_s = static_cast<double>(k) * kLiveScorePeriod_s;
    series.samples[k].specific_force_m_s2 = heard.specific_force_m_s2;
    series.samples[k].angular_velocity_rad_s = heard.angular_velocity_rad_s;
  }
  return series;
}

// The tangent at knot k from its neighbours' stamps (one-sided at the ends).
Vector6 Tangent(const std::vector<StampedPose>& poses, std::size_t k) {
  const std::size_t before = k == 0 ? 0 : k - 1, after = std::min(k + 1, poses.size() - 1);
  const double span_s = static_cast<double>(poses[after].utime - poses[before].utime) * 1e-6;
  return span_s > 0.0 ? Vector6((poses[after].pose - poses[before].pose) / span_s) : Vector6::Zero();
}

// The poses at each instant of the grid: a cubic Hermite curve through
// them with Catmull-Rom tangents on their own stamps. A stream slower than
// the grid (the encoders' pose at 100 Hz) then has a continuous velocity,
// where straight lines between its poses would put its whole acceleration
// into spikes at the poses when the grid's motion is differentiated.
std::vector<Pose> PosesOnGrid(const std::vector<StampedPose>& poses, std::int64_t start, std::size_t n) {
  std::vector<Pose> out(n);
  std::size_t next = 1;
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t t = start + static_cast<std::int64_t>(k) * kPeriodUs;
    while (next + 1 < poses.size() && poses[next].utime < t) ++next;
    const StampedPose& a = poses[next - 1];
    const StampedPose& b = poses[next];
    const double span_s = static_cast<double>(b.utime - a.utime) * 1e-6;
    if (!(span_s > 0.0)) {
      out[k] = Pose::FromVector(b.pose);
      continue;
    }
    const double x = std::clamp(static_cast<double>(t - a.utime) * 1e-6 / span_s, 0.0, 1.0);
    const double x2 = x * x, x3 = x2 * x;
    const Vector6 p = (2 * x3 - 3 * x2 + 1) * a.pose + (x3 - 2 * x2 + x) * span_s * Tangent(poses, next - 1) +
                      (-2 * x3 + 3 * x2) * b.pose + (x3 - x2) * span_s * Tangent(poses, next);
    out[k] = Pose::FromVector(p);
  }
  return out;
}

struct Window {
  std::int64_t start = 0, end = 0;
  std::int64_t length() const { return std::max<std::int64_t>(end - start, 0); }
};

// The longest time the vehicle was heard without a silence the cueing took
// for a lost input (no sample for [input] timeout_s) within [from, to].
Window LongestHeard(const std::vector<HeardVehicleSample>& vehicle, std::int64_t timeout_us, std::int64_t from,
                    std::int64_t to) {
  Window best{from, from};
  std::size_t first = 0;
  for (std::size_t k = 1; k <= vehicle.size(); ++k) {
    if (k < vehicle.size() && vehicle[k].utime - vehicle[k - 1].utime <= timeout_us) continue;
    const Window heard{std::max(vehicle[first].utime, from), std::min(vehicle[k - 1].utime, to)};
    if (heard.length() > best.length()) best = heard;
    first = k;
  }
  return best;
}

bool Spans(const std::vector<StampedPose>& poses, std::int64_t start, std::int64_t end) {
  return poses.size() >= 2 && poses.front().utime <= start && poses.back().utime >= end;
}

}  // namespace

LiveCueingScore ScoreLiveCueing(const CueingConfig& config, const std::vector<HeardVehicleSample>& vehicle,
                                const std::vector<StampedPose>& commanded, const std::vector<StampedPose>& real) {
  if (vehicle.empty()) throw std::invalid_argument("no vehicle sample to score against");
  if (commanded.size() < 2) throw std::invalid_argument("no commanded poses while cueing");
  const Window heard = LongestHeard(vehicle, std::llround(config.input.timeout_s * 1e6), commanded.front().utime,
                                    commanded.back().utime);
  if (heard.length() < 10 * kPeriodUs) {
    throw std::invalid_argument(fmt::format("the vehicle was heard for {:.3f} s while the planner followed the cueing",
                                            static_cast<double>(heard.length()) * 1e-6));
  }
  const std::int64_t start = heard.start, end = heard.end;
  const auto n = static_cast<std::size_t>((end - start) / kPeriodUs) + 1;
  LiveCueingScore out;
  out.start_utime = start;
  out.grid_samples = n;
  out.duration_s = static_cast<double>(n - 1) * kLiveScorePeriod_s;
  const VehicleSeries felt = HeldVehicle(vehicle, start, n);
  const auto score = [&](const std::vector<StampedPose>& poses) {
    return ScorePerception(
        config.perception, felt,
        PlatformMotionAtHead(PosesOnGrid(poses, start, n), kLiveScorePeriod_s, config.head_in_platform_m));
  };
  out.commanded = score(commanded);
  if (Spans(real, start, start + static_cast<std::int64_t>(n - 1) * kPeriodUs)) out.real = score(real);
  return out;
}

}  // namespace edsp
