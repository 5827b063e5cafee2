#pragma once
// The cueing algorithms, by name, behind one interface: what turns the
// vehicle's samples into the rider's head cue, one setpoint period a step
// (classical washout, cueing/classical_washout.h; model-predictive,
// cueing/mpc_cueing.h).

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "edsp/cueing/classical_washout.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct CueingConfig;  // cueing_config.h, which names its algorithm by this header's enum

enum class CueingAlgorithm { kClassicalWashout, kModelPredictive };
inline constexpr CueingAlgorithm kCueingAlgorithms[] = {CueingAlgorithm::kClassicalWashout,
                                                        CueingAlgorithm::kModelPredictive};

// "classical_washout", "mpc": as the config's [cueing] algorithm and the bench's JSON spell them.
const char* CueingAlgorithmName(CueingAlgorithm algorithm);
std::optional<CueingAlgorithm> CueingAlgorithmFromName(std::string_view name);

class CueingFilter {
 public:
  virtual ~CueingFilter() = default;
  // The head's displacement from its neutral pose for this sample (throws
  // std::invalid_argument for one that is not finite).
  virtual HeadCue Step(const VehicleSample& sample) = 0;
  // Back at the neutral pose with a rider at rest, as when made.
  virtual void Reset() = 0;
  // Solves that stopped at their iteration limit (model-predictive cueing; 0 for a filter).
  virtual std::int64_t unconverged_solves() const = 0;
};

// Classical washout alone needs no platform model.
std::unique_ptr<CueingFilter> MakeClassicalWashout(const ClassicalWashoutParameters& parameters, double period_s);

// About the model's home pose, at the config's rate. Throws
// std::invalid_argument naming what is wrong in the config.
std::unique_ptr<CueingFilter> MakeCueingFilter(CueingAlgorithm algorithm, const PlatformModel& model,
                                               const CueingConfig& config);

}  // namespace edsp
