#include "edsp/cueing/cueing_soak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "edsp/kinematics/path_check.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {
namespace {

// The conditioning changes slowly: checked every this many cycles, as the
// whole-path check does it every 2 mm of leg travel.
constexpr std::int64_t kConditioningEvery = 50;

double Percentile(std::vector<float> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return static_cast<double>(values[k]);
}

// Why the setpoint of `cycle` is refused, or empty.
std::string Refusal(const PlatformModel& model, const PathLimits& limits, const Pose& pose, const Vector6& legs,
                    const Vector6& previous, const Vector6& before, double period_s, std::int64_t cycle) {
  const WorkspaceCheck legs_check = CheckLegs(model, model.Solve(pose));
  if (!legs_check.ok()) return legs_check.Describe();
  if (cycle % kConditioningEvery == 0) {
    const WorkspaceCheck conditioning = CheckConditioning(model, pose);
    if (!conditioning.ok()) return conditioning.Describe();
  }
  if (cycle < 2) return "";
  const double speed = ((legs - previous) / period_s).cwiseAbs().maxCoeff();
  if (speed > limits.leg_speed_max_m_s) return fmt::format("a leg at {:.3f} m/s", speed);
  const double accel = ((legs - 2.0 * previous + before) / (period_s * period_s)).cwiseAbs().maxCoeff();
  if (limits.leg_accel_max_m_s2 > 0.0 && accel > limits.leg_accel_max_m_s2) {
    return fmt::format("a leg accelerating at {:.2f} m/s^2", accel);
  }
  return "";
}

}  // namespace

CueingSoak SoakCueing(const PlatformModel& model, const CueingConfig& config, CueingAlgorithm algorithm,
                      const RandomVehicleParameters& vehicle, std::int64_t cycles, std::uint64_t seed) {
  const double period_s = 1.0 / config.rate_hz;
  const std::unique_ptr<CueingFilter> filter = MakeCueingFilter(algorithm, model, config);
  // A solve every this many steps (classical washout: every step).
  const std::int64_t solve_every =
      algorithm == CueingAlgorithm::kModelPredictive
          ? std::max<std::int64_t>(1, std::llround(config.mpc.horizon.solve_period_s / period_s))
          : 1;
  std::vector<float> solve_us;
  solve_us.reserve(static_cast<std::size_t>(cycles / solve_every + 1));
  RandomVehicle source(vehicle, period_s, seed);
  const PathLimits limits = PathLimitsOf(model);
  const WorkspaceLimits& workspace = model.config().limits;
  const Vector6& home = model.home_length_m();
  CueingSoak soak;
  soak.cycles = cycles;
  std::vector<float> step_us;  // floats: 10^7 cycles in 40 MB
  step_us.reserve(static_cast<std::size_t>(cycles));
  Vector6 previous = home, before = home;
  for (std::int64_t cycle = 0; cycle < cycles; ++cycle) {
    const VehicleSample sample = source.Next();
    const auto start = std::chrono::steady_clock::now();
    const HeadCue cue = filter->Step(sample);
    step_us.push_back(std::chrono::duration<float, std::micro>(std::chrono::steady_clock::now() - start).count());
    if (cycle % solve_every == 0) solve_us.push_back(step_us.back());
    const Pose pose = CueToPlatformPose(model.home_pose(), config.head_in_platform_m, cue);
    const Vector6 legs = model.LegLengths(pose);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const double room = std::min(home(leg) - workspace.leg_min_m, workspace.leg_max_m - home(leg));
      soak.peak_stroke_used = std::max(soak.peak_stroke_used, std::fabs(legs(leg) - home(leg)) / room);
    }
    const std::string why = Refusal(model, limits, pose, legs, previous, before, period_s, cycle);
    if (!why.empty()) {
      if (soak.refused_setpoints++ == 0) soak.first_refusal = fmt::format("at cycle {}: {}", cycle, why);
    }
    before = previous;
    previous = legs;
  }
  soak.step_p50_us = Percentile(step_us, 0.5);
  soak.step_p99_us = Percentile(step_us, 0.99);
  soak.unconverged_solves = filter->unconverged_solves();
  soak.solve_p50_us = Percentile(solve_us, 0.5);
  soak.solve_p99_us = Percentile(solve_us, 0.99);
  soak.solve_max_us = solve_us.empty() ? 0.0 : static_cast<double>(*std::max_element(solve_us.begin(), solve_us.end()));
  return soak;
}

}  // namespace edsp
