#pragma once
// A cueing configuration file (config/cueing.toml; docs/cueing.md): where
// the rider's head sits on the platform, when the vehicle's input counts as
// lost and how it fades, the washout's gains, break
// frequencies and limits, the model-predictive cueing's box, penalties and
// horizon, and the vestibular models' parameters. Every
// key is checked; a bad file throws ConfigError naming the file, the line,
// the [section] key and the value.

#include <string>

#include "edsp/config_file/config_error.h"
#include "edsp/cueing/classical_washout.h"
#include "edsp/cueing/cueing_algorithm.h"
#include "edsp/cueing/mpc_cueing.h"
#include "edsp/cueing/vehicle_input.h"
#include "edsp/cueing/vestibular.h"

namespace edsp {

struct CueingConfig {
  double rate_hz = 1000.0;                                         // setpoints out
  CueingAlgorithm algorithm = CueingAlgorithm::kClassicalWashout;  // what edsp-cueing live runs
  Vector3 head_in_platform_m = Vector3(0.0, 0.0, 0.8);             // the rider's head in {M}
  VehicleInputParameters input;
  ClassicalWashoutParameters washout;
  MpcCueingParameters mpc;
  VestibularParameters perception;
};

CueingConfig LoadCueingConfig(const std::string& path);
CueingConfig ParseCueingConfig(const std::string& toml_text, const std::string& origin);

}  // namespace edsp
