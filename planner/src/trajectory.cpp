#include "edsp/planner/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {

namespace {

// s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its first two derivatives in τ.
struct Quintic {
  double s, ds, dds;
};
Quintic QuinticProfile(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  const double t2 = tau * tau, t3 = t2 * tau;
  return {t3 * (10.0 - 15.0 * tau + 6.0 * t2), 30.0 * t2 * (1.0 - 2.0 * tau + t2),
          60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2)};
}

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("{} = {} must be positive and finite", what, value));
  }
}

}  // namespace

QuinticMove::QuinticMove(const Vector6& from, const Vector6& to, double duration_s)
    : from_(from), to_(to), duration_s_(duration_s) {
  RequirePositive(duration_s, "quintic move duration_s");
  if (!from.allFinite() || !to.allFinite()) {
    throw std::invalid_argument("quintic move: non-finite start or end pose");
  }
}

QuinticMove QuinticMove::WithinLimits(const Vector6& from, const Vector6& to, double max_speed_m_s,
                                      double max_speed_rad_s) {
  RequirePositive(max_speed_m_s, "max_speed_m_s");
  RequirePositive(max_speed_rad_s, "max_speed_rad_s");
  // Peak speed of the quintic is 15/8 · distance / duration.
  const Vector6 delta = to - from;
  const double duration = 1.875 * std::max(delta.head<3>().cwiseAbs().maxCoeff() / max_speed_m_s,
                                           delta.tail<3>().cwiseAbs().maxCoeff() / max_speed_rad_s);
  return QuinticMove(from, to, std::max(duration, 1e-3));
}

PoseSample QuinticMove::Sample(double t_s) const {
  const Quintic q = QuinticProfile(t_s / duration_s_);
  const Vector6 delta = to_ - from_;
  PoseSample sample;
  sample.pose = from_ + q.s * delta;
  sample.velocity = q.ds / duration_s_ * delta;
  sample.acceleration = q.dds / (duration_s_ * duration_s_) * delta;
  return sample;
}

Sinusoid::Sinusoid(const Vector6& center, int axis, double amplitude, double frequency_hz, int cycles)
    : center_(center), axis_(axis), amplitude_(amplitude), frequency_hz_(frequency_hz), cycles_(cycles) {
  if (axis < 0 || axis > 5) throw std::invalid_argument(fmt::format("sinusoid axis {} not in 0..5", axis));
  RequirePositive(frequency_hz, "sinusoid frequency_hz");
  if (cycles < 2) throw std::invalid_argument("sinusoid needs at least 2 cycles (fade in, fade out)");
  if (!std::isfinite(amplitude) || !center.allFinite()) {
    throw std::invalid_argument("sinusoid: non-finite centre or amplitude");
  }
}

PoseSample Sinusoid::Sample(double t_s) const {
  const double period = 1.0 / frequency_hz_;
  const double duration = cycles_ * period;
  const double t = std::clamp(t_s, 0.0, duration);
  // Window w(t): quintic rise over the first period, fall over the last.
  Quintic w{1.0, 0.0, 0.0};
  double sign = 1.0;
  if (t < period) {
    w = QuinticProfile(t / period);
  } else if (t > duration - period) {
    w = QuinticProfile((duration - t) / period);
    sign = -1.0;
  }
  const double w1 = sign * w.ds / period, w2 = w.dds / (period * period);
  const double phase = kTwoPi * frequency_hz_ * t, omega = kTwoPi * frequency_hz_;
  const double s = std::sin(phase), c = std::cos(phase);
  PoseSample sample;  // zero velocity and acceleration on the other axes
  sample.pose = center_;
  sample.pose(axis_) += amplitude_ * w.s * s;
  sample.velocity(axis_) = amplitude_ * (w1 * s + w.s * omega * c);
  sample.acceleration(axis_) = amplitude_ * (w2 * s + 2.0 * w1 * omega * c - w.s * omega * omega * s);
  return sample;
}

void TrajectorySequence::Append(std::string name, std::unique_ptr<Trajectory> segment) {
  const double duration = segment->duration_s();
  if (!segments_.empty()) {
    const Vector6 gap = segment->Sample(0.0).pose - EndPose();
    if (gap.cwiseAbs().maxCoeff() > 1e-9) {
      throw std::invalid_argument(fmt::format("segment \"{}\" starts {:.3g} away from where \"{}\" ends: a jump", name,
                                              gap.cwiseAbs().maxCoeff(), segments_.back().name));
    }
  }
  segments_.push_back({std::move(name), total_s_, std::move(segment)});
  total_s_ += duration;
}

int TrajectorySequence::SegmentAt(double t_s) const {
  if (segments_.empty()) return -1;
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), t_s,
                                   [](double t, const Segment& s) { return t < s.start_s; });
  return std::max(0, static_cast<int>(it - segments_.begin()) - 1);
}

PoseSample TrajectorySequence::Sample(double t_s) const {
  if (segments_.empty()) throw std::logic_error("empty trajectory sequence");
  const Segment& s = segments_[static_cast<std::size_t>(SegmentAt(t_s))];
  return s.trajectory->Sample(t_s - s.start_s);
}

Vector6 TrajectorySequence::EndPose() const {
  const Segment& last = segments_.back();
  return last.trajectory->Sample(last.trajectory->duration_s()).pose;
}

}  // namespace edsp
