#include "edsp/cueing/cueing_algorithm.h"

#include <type_traits>
#include <utility>

#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/mpc_cueing.h"

namespace edsp {
namespace {

template <typename Algorithm>
class FilterOf final : public CueingFilter {
 public:
  template <typename... Args>
  explicit FilterOf(Args&&... args) : algorithm_(std::forward<Args>(args)...) {}
  HeadCue Step(const VehicleSample& sample) override { return algorithm_.Step(sample); }
  void Reset() override { algorithm_.Reset(); }
  std::int64_t unconverged_solves() const override {
    if constexpr (std::is_same_v<Algorithm, MpcCueing>) {
      return algorithm_.unconverged_solves();
    } else {
      return 0;
    }
  }

 private:
  Algorithm algorithm_;
};

}  // namespace

const char* CueingAlgorithmName(CueingAlgorithm algorithm) {
  switch (algorithm) {
    case CueingAlgorithm::kClassicalWashout: return "classical_washout";
    case CueingAlgorithm::kModelPredictive: return "mpc";
  }
  return "unknown";
}

std::optional<CueingAlgorithm> CueingAlgorithmFromName(std::string_view name) {
  for (CueingAlgorithm algorithm : kCueingAlgorithms) {
    if (name == CueingAlgorithmName(algorithm)) return algorithm;
  }
  return std::nullopt;
}

std::unique_ptr<CueingFilter> MakeCueingFilter(CueingAlgorithm algorithm, const PlatformModel& model,
                                               const CueingConfig& config) {
  const double period_s = 1.0 / config.rate_hz;
  if (algorithm == CueingAlgorithm::kModelPredictive) {
    return std::make_unique<FilterOf<MpcCueing>>(model, model.home_pose(), config.head_in_platform_m, config.perception,
                                                 config.mpc, period_s);
  }
  return MakeClassicalWashout(config.washout, period_s);
}

std::unique_ptr<CueingFilter> MakeClassicalWashout(const ClassicalWashoutParameters& parameters, double period_s) {
  return std::make_unique<FilterOf<ClassicalWashout>>(parameters, period_s);
}

}  // namespace edsp
