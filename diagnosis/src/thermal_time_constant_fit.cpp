#include "edsp/diagnosis/thermal_time_constant_fit.h"

#include "edsp/diagnosis/linear_fit.h"

namespace edsp::gap {

namespace {

// Held-out MSE of the frame and `selected` with the bases at `design`.
double ScoreAt(const PlatformModel& model, const MeasurementData& data, const DesignOptions& design,
               const std::vector<Effect>& selected, double sigma2, const TimeOffset& clock) {
  Design full = BuildDesign(model, data, design);
  if (clock.applied) RemoveTimeOffset(clock.offset_s, &full);
  const Design kept = KeepOnly(full, selected);
  const GramSet gram(kept, MakeFolds(kept));
  return HeldOutMse(gram, ColumnsOf(kept, selected), PriorWeights(kept, sigma2));
}

}  // namespace

ThermalTimeConstantChoice ChooseThermalTimeConstant(const PlatformModel& model, const MeasurementData& data,
                                                    const DesignOptions& design, const std::vector<double>& grid_s,
                                                    const std::vector<Effect>& selected, double sigma2,
                                                    const TimeOffset& clock) {
  ThermalTimeConstantChoice choice;
  choice.tau_s = design.thermal_time_constant_s;
  choice.heldout_mse = choice.heldout_mse_as_given = ScoreAt(model, data, design, selected, sigma2, clock);
  for (double tau : grid_s) {
    if (tau == design.thermal_time_constant_s) continue;
    DesignOptions at = design;
    at.thermal_time_constant_s = tau;
    const double mse = ScoreAt(model, data, at, selected, sigma2, clock);
    if (mse < choice.heldout_mse) choice.tau_s = tau, choice.heldout_mse = mse;
  }
  return choice;
}

}  // namespace edsp::gap
