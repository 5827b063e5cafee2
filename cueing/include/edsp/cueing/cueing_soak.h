#pragma once
// A long run of random vehicle motion through a cueing algorithm, every
// setpoint judged as the kinematics and the bridge would: its legs within
// their strokes and joint angles, away from a singularity, and the legs'
// speed and acceleration between successive setpoints within the drives'.
// Classical washout has no limits of its own beyond its filters' scale:
// this counts how often a rough ride would be refused; the model-predictive
// cueing keeps every setpoint inside by construction, and this checks it.

#include <cstdint>
#include <string>

#include "edsp/cueing/cueing_algorithm.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/random_vehicle.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct CueingSoak {
  std::int64_t cycles = 0;
  std::int64_t refused_setpoints = 0;           // setpoints the checks refuse
  std::string first_refusal;                    // "at cycle N: …", or empty
  double peak_stroke_used = 0.0;                // as CueingRun's
  double step_p50_us = 0.0, step_p99_us = 0.0;  // one step, timed (float resolution)
  // The steps that solved (the model-predictive cueing's, one per solve
  // period; every step for classical washout), timed.
  double solve_p50_us = 0.0, solve_p99_us = 0.0, solve_max_us = 0.0;
  std::int64_t unconverged_solves = 0;  // stopped at the iteration limit
};

CueingSoak SoakCueing(const PlatformModel& model, const CueingConfig& config, CueingAlgorithm algorithm,
                      const RandomVehicleParameters& vehicle, std::int64_t cycles, std::uint64_t seed);

}  // namespace edsp
