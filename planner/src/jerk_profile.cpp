#include "edsp/planner/jerk_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edsp {

namespace {

ScalarState Advance(const ScalarState& s, double jerk, double t) {
  return {s.position + s.velocity * t + s.acceleration * t * t / 2.0 + jerk * t * t * t / 6.0,
          s.velocity + s.acceleration * t + jerk * t * t / 2.0, s.acceleration + jerk * t};
}

}  // namespace

void JerkProfile::Append(double duration_s, double jerk) {
  if (!(duration_s > 0.0)) return;
  const ScalarState from =
      pieces_.empty() ? start_ : Advance(piece_start_.back(), pieces_.back().second, pieces_.back().first);
  pieces_.emplace_back(duration_s, jerk);
  piece_start_.push_back(from);
  duration_s_ += duration_s;
}

JerkProfile JerkProfile::RestToRest(double h, const ScalarLimits& l) {
  if (!(l.velocity > 0.0 && l.acceleration > 0.0 && l.jerk > 0.0)) {
    throw std::invalid_argument("JerkProfile::RestToRest: limits must be positive");
  }
  JerkProfile p;
  if (!(h > 0.0)) return p;
  const double v = l.velocity, a = l.acceleration, j = l.jerk;
  // Acceleration phase reaching the velocity limit (with or without the acceleration limit).
  double tj = v * j >= a * a ? a / j : std::sqrt(v / j);
  double ta = v * j >= a * a ? tj + v / a : 2.0 * tj;
  double tv = h / v - ta;
  if (tv < 0.0) {  // too short to cruise
    tv = 0.0;
    if (h >= 2.0 * a * a * a / (j * j)) {
      tj = a / j;
      ta = tj / 2.0 + std::sqrt(tj * tj / 4.0 + h / a);
    } else {
      tj = std::cbrt(h / (2.0 * j));
      ta = 2.0 * tj;
    }
  }
  const double hold = std::max(0.0, ta - 2.0 * tj);
  p.Append(tj, j);
  p.Append(hold, 0.0);
  p.Append(tj, -j);
  p.Append(tv, 0.0);
  p.Append(tj, -j);
  p.Append(hold, 0.0);
  p.Append(tj, j);
  return p;
}

JerkProfile JerkProfile::StopFrom(const ScalarState& s, double a_max, double j) {
  if (!(a_max > 0.0 && j > 0.0)) throw std::invalid_argument("JerkProfile::StopFrom: limits must be positive");
  JerkProfile p;
  p.start_ = s;
  const double v = std::max(0.0, s.velocity), a = s.acceleration;
  if (a < 0.0 && v <= a * a / (2.0 * j)) {
    // Already decelerating as hard as the jerk allows: release it to zero.
    p.Append(-a / j, j);
    return p;
  }
  // Ramp to −peak, hold, ramp back to zero so velocity and acceleration end together.
  double peak = a_max;
  double hold = (v + (a * a - 2.0 * peak * peak) / (2.0 * j)) / peak;
  if (hold < 0.0) {
    peak = std::sqrt(v * j + a * a / 2.0);
    hold = 0.0;
  }
  p.Append(std::max(0.0, (a + peak) / j), -j);
  p.Append(hold, 0.0);
  p.Append(peak / j, j);
  return p;
}

JerkProfile JerkProfile::Clock(double duration) {
  JerkProfile p;
  p.start_ = {0.0, 1.0, 0.0};
  p.Append(duration, 0.0);
  return p;
}

ScalarState JerkProfile::At(double t) const {
  t = std::clamp(t, 0.0, duration_s_);
  if (pieces_.empty()) return start_;
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    if (t <= pieces_[k].first || k + 1 == pieces_.size()) {
      return Advance(piece_start_[k], pieces_[k].second, std::min(t, pieces_[k].first));
    }
    t -= pieces_[k].first;
  }
  return start_;
}

}  // namespace edsp
