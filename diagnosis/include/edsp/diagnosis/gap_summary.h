#pragma once
// Where the gap lies: the residual at point A (after the tracker frame is
// estimated) broken down by run, by leg (projected into leg space through the
// kinematics), by direction of leg motion, by motion phase, by pose region
// and over time; with encoder data, split into servo tracking (command vs
// encoder) and mechanism (encoder vs measurement).

#include <array>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct RmsMax {
  double rms_m = 0.0, max_m = 0.0;
  int samples = 0;
};

struct GapSummary {
  RmsMax overall;
  std::vector<std::pair<std::string, RmsMax>> by_run;
  std::array<double, 6> by_leg_m{};                               // RMS of the min-norm leg-space residual
  std::array<double, 6> extending_mean_m{}, retracting_mean_m{};  // its mean by direction, per leg
  std::map<std::string, RmsMax> by_phase;                         // at_rest, accelerating, cruising
  std::map<std::string, RmsMax> by_region;                        // near, mid, far from home (terciles)
  std::vector<std::pair<double, RmsMax>> over_time;               // start time of each tenth of the samples
  bool has_encoder = false;
  // RMS of command − encoder, per leg: where the design took the drives'
  // rest out of the residual (design.h), the part servo_lag's terms describe.
  std::array<double, 6> servo_tracking_m{};
  RmsMax mechanism;   // residual once the encoders' legs are used
  std::string where;  // the above in a sentence or three
};

// `residual`: 3 values per sample of `design`.
GapSummary SummarizeGap(const Design& design, const Eigen::VectorXd& residual);

nlohmann::json ToJson(const GapSummary& gap);

// RMS and max of |residual| over samples [begin, begin + count).
RmsMax PointStats(const Eigen::VectorXd& residual, int begin, int count);

}  // namespace edsp::gap
