#include "edsp/diagnosis/thermal_time_constant_fit.h"

#include "edsp/diagnosis/heldout_score.h"

namespace edsp::gap {

ThermalTimeConstantChoice ChooseThermalTimeConstant(const PlatformModel& model, const MeasurementData& data,
                                                    const DesignOptions& design, const std::vector<double>& grid_s,
                                                    const std::vector<Effect>& selected, double sigma2,
                                                    const TimeOffset& clock) {
  ThermalTimeConstantChoice choice;
  choice.tau_s = design.thermal_time_constant_s;
  choice.heldout_mse = choice.heldout_mse_as_given = HeldOutMseOf(model, data, design, selected, sigma2, clock);
  for (double tau : grid_s) {
    if (tau == design.thermal_time_constant_s) continue;
    DesignOptions at = design;
    at.thermal_time_constant_s = tau;
    const double mse = HeldOutMseOf(model, data, at, selected, sigma2, clock);
    if (mse < choice.heldout_mse) choice.tau_s = tau, choice.heldout_mse = mse;
  }
  return choice;
}

}  // namespace edsp::gap
