#pragma once
// The second rig's test motions, written apart from planner/: the paper's
// single-axis motions (L*, R*: home, then `stops` poses across ±range, a dwell
// at each, home) and mixed ones (M<k>: every axis at once, poses drawn from k)
// as minimum-jerk moves between dwells. And motions another controller plays
// (edsp's planned ones), given as samples.

#include <string>
#include <vector>

#include "edsp/blindrig/blind_kinematics.h"

namespace edsp::blind {

struct MotionLimits {
  int stops = 5;
  double dwell_s = 1.0;
  double linear_range_m = 0.5;
  double angular_range_rad = 0.5235987755982988;  // 30°
  double linear_speed_m_s = 0.1;                  // peak speed of a move
  double angular_speed_rad_s = 0.2;
};

// A motion sampled at `rate_hz` from its first instant to its last: the
// poses and their second derivatives (x y z roll pitch yaw), between samples
// linearly.
struct SampledMotion {
  std::string name;
  double rate_hz = 1000.0;
  std::vector<Vec6> poses, accelerations;
};

// Whether `name` is one of this rig's own motions.
bool IsBlindMotionName(const std::string& name);

class BlindMotion {
 public:
  // Names: Lx Ly Lz Rx Ry Rz, M<k> (k ≥ 1). Throws std::invalid_argument.
  BlindMotion(const std::string& name, const Vec6& home, const MotionLimits& limits = {});
  // Throws std::invalid_argument for fewer than two samples, poses and
  // accelerations of different counts, or a rate that is not positive.
  explicit BlindMotion(SampledMotion sampled);

  const std::string& name() const { return name_; }
  double duration_s() const;
  // The pose at time t (clamped to the motion), and its second derivative.
  Vec6 Pose(double t) const;
  Vec6 Acceleration(double t) const;

 private:
  void AddMove(const Vec6& to, const MotionLimits& limits);
  void AddDwell(double seconds);
  std::size_t Segment(double t) const;

  std::string name_;
  std::vector<Vec6> from_, to_;  // per segment
  std::vector<double> end_s_;    // segment end times
  SampledMotion sampled_;        // instead of segments, when it has samples
};

}  // namespace edsp::blind
