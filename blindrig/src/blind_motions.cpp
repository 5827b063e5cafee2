#include "edsp/blindrig/blind_motions.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

namespace edsp::blind {

namespace {

// Minimum-jerk blend s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its derivatives in τ; its
// peak speed is 1.875 × distance / duration.
constexpr double kPeakSpeedFactor = 1.875;
double Blend(double tau) { return tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau); }
double BlendSecond(double tau) { return tau * (60.0 - 180.0 * tau + 120.0 * tau * tau); }

int AxisOf(char kind, char axis) {
  const int offset = kind == 'L' ? 0 : 3;
  if (axis < 'x' || axis > 'z') return -1;
  return offset + (axis - 'x');
}

}  // namespace

BlindMotion::BlindMotion(const std::string& name, const Vec6& home, const MotionLimits& limits) : name_(name) {
  from_.push_back(home), to_.push_back(home), end_s_.push_back(0.0);
  const auto range = [&](int axis) { return axis < 3 ? limits.linear_range_m : limits.angular_range_rad; };
  if (name.size() == 2 && (name[0] == 'L' || name[0] == 'R') && AxisOf(name[0], name[1]) >= 0) {
    const int axis = AxisOf(name[0], name[1]);
    for (int k = 0; k < limits.stops; ++k) {
      Vec6 stop = home;
      stop(axis) += range(axis) * (-1.0 + 2.0 * k / std::max(1, limits.stops - 1));
      AddMove(stop, limits);
      AddDwell(limits.dwell_s);
    }
  } else if (name.size() >= 2 && name[0] == 'M' && std::all_of(name.begin() + 1, name.end(), ::isdigit)) {
    std::mt19937_64 draw(0x5eed0000ULL + std::stoull(name.substr(1)));
    std::uniform_real_distribution<double> unit(-0.35, 0.35);
    MotionLimits mixed = limits;
    mixed.linear_speed_m_s *= 0.5, mixed.angular_speed_rad_s *= 0.5;
    for (int k = 0; k < limits.stops; ++k) {
      Vec6 stop = home;
      for (int axis = 0; axis < 6; ++axis) stop(axis) += range(axis) * unit(draw);
      AddMove(stop, mixed);
      AddDwell(limits.dwell_s);
    }
  } else {
    throw std::invalid_argument("blind rig: unknown motion '" + name + "' (Lx Ly Lz Rx Ry Rz or M<k>)");
  }
  AddMove(home, limits);
  AddDwell(limits.dwell_s);
}

void BlindMotion::AddMove(const Vec6& to, const MotionLimits& limits) {
  const Vec6 from = to_.back();
  const double linear = (to - from).head<3>().norm(), angular = (to - from).tail<3>().cwiseAbs().maxCoeff();
  const double seconds = std::max({kPeakSpeedFactor * linear / limits.linear_speed_m_s,
                                   kPeakSpeedFactor * angular / limits.angular_speed_rad_s, 0.2});
  from_.push_back(from), to_.push_back(to), end_s_.push_back(end_s_.back() + seconds);
}

void BlindMotion::AddDwell(double seconds) {
  from_.push_back(to_.back()), to_.push_back(to_.back()), end_s_.push_back(end_s_.back() + seconds);
}

std::size_t BlindMotion::Segment(double t) const {
  const auto it = std::lower_bound(end_s_.begin(), end_s_.end(), t);
  return std::min<std::size_t>(static_cast<std::size_t>(it - end_s_.begin()), end_s_.size() - 1);
}

bool IsBlindMotionName(const std::string& name) {
  if (name.size() == 2 && (name[0] == 'L' || name[0] == 'R') && name[1] >= 'x' && name[1] <= 'z') return true;
  return name.size() >= 2 && name[0] == 'M' &&
         std::all_of(name.begin() + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; }) && name != "M0";
}

BlindMotion::BlindMotion(SampledMotion sampled) : name_(sampled.name), sampled_(std::move(sampled)) {
  if (sampled_.poses.size() < 2 || sampled_.accelerations.size() != sampled_.poses.size() || !(sampled_.rate_hz > 0)) {
    throw std::invalid_argument("sampled motion " + name_ + ": needs two or more poses, an acceleration for each, " +
                                "and a positive rate");
  }
}

double BlindMotion::duration_s() const {
  if (!sampled_.poses.empty()) return static_cast<double>(sampled_.poses.size() - 1) / sampled_.rate_hz;
  return end_s_.back();
}

namespace {

// Between the samples around t, linearly; before the first and after the
// last, those.
Vec6 Interpolated(const std::vector<Vec6>& samples, double rate_hz, double t) {
  const double u = std::clamp(t * rate_hz, 0.0, static_cast<double>(samples.size() - 1));
  const auto k = std::min(static_cast<std::size_t>(u), samples.size() - 2);
  const double w = u - static_cast<double>(k);
  return samples[k] + w * (samples[k + 1] - samples[k]);
}

}  // namespace

Vec6 BlindMotion::Pose(double t) const {
  if (!sampled_.poses.empty()) return Interpolated(sampled_.poses, sampled_.rate_hz, t);
  const std::size_t s = Segment(t);
  if (s == 0) return from_[0];
  const double begin = end_s_[s - 1], length = end_s_[s] - begin;
  const double tau = std::clamp((t - begin) / length, 0.0, 1.0);
  return from_[s] + Blend(tau) * (to_[s] - from_[s]);
}

Vec6 BlindMotion::Acceleration(double t) const {
  if (!sampled_.poses.empty()) {
    if (t <= 0.0 || t >= duration_s()) return Vec6::Zero();
    return Interpolated(sampled_.accelerations, sampled_.rate_hz, t);
  }
  const std::size_t s = Segment(t);
  if (s == 0 || t >= end_s_.back()) return Vec6::Zero();
  const double begin = end_s_[s - 1], length = end_s_[s] - begin;
  const double tau = std::clamp((t - begin) / length, 0.0, 1.0);
  return BlendSecond(tau) / (length * length) * (to_[s] - from_[s]);
}

}  // namespace edsp::blind
