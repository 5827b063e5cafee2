#include "edsp/diagnosis/heldout_score.h"

#include <algorithm>
#include <cmath>

#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/structural_mode_fit.h"
#include "edsp/diagnosis/thermal_time_constant_fit.h"

namespace edsp::gap {

double HeldOutMseOf(const PlatformModel& model, const MeasurementData& data, const DesignOptions& design,
                    const std::vector<Effect>& effects, double sigma2, const TimeOffset& clock) {
  Design full = BuildDesign(model, data, design);
  if (clock.applied) RemoveTimeOffset(clock.offset_s, &full);
  const Design kept = KeepOnly(full, effects);
  const GramSet gram(kept, MakeFolds(kept));
  return HeldOutMse(gram, ColumnsOf(kept, effects), PriorWeights(kept, sigma2));
}

double HeldOutRmsOf(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                    const Diagnosis& d, const std::vector<Effect>& effects) {
  const MeasurementData fitted = Decimated(data, options.max_rate_hz);
  const double sigma2 = d.prior_sigma2;
  auto has = [](const std::vector<Effect>& set, Effect e) { return std::find(set.begin(), set.end(), e) != set.end(); };
  DesignOptions design = d.design;
  if (has(effects, Effect::kStructuralResonance) && design.structural_mode_hz <= 0.0) {
    Design full = BuildDesign(model, fitted, design);
    if (d.time_offset.applied) RemoveTimeOffset(d.time_offset.offset_s, &full);
    std::vector<Effect> others;
    for (Effect e : effects) {
      if (e != Effect::kStructuralResonance) others.push_back(e);
    }
    const StructuralModeChoice mode = ChooseStructuralMode(full, others, sigma2, 0.0);
    design.structural_mode_hz = mode.hz;
    design.structural_mode_damping = mode.damping;
  }
  if (has(effects, Effect::kThermalDrift) && !has(d.selected, Effect::kThermalDrift) &&
      !options.thermal_time_constants_s.empty()) {
    design.thermal_time_constant_s = ChooseThermalTimeConstant(model, fitted, design, options.thermal_time_constants_s,
                                                               effects, sigma2, d.time_offset)
                                         .tau_s;
  }
  // Three coordinates per sample: the RMS at A is √(3·MSE).
  return std::sqrt(3.0 * HeldOutMseOf(model, fitted, design, effects, sigma2, d.time_offset));
}

}  // namespace edsp::gap
