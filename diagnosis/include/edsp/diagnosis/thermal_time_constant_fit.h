#pragma once
// The thermal basis's one non-linear parameter, the screws' cooling time
// constant: each constant of a grid is scored by how well the tracker frame
// and the effects a pass selected predict the held-out runs with the
// thermal columns at that constant. A candidate costs one design and one
// small fit (the frame and the selected effects' columns), not a diagnosis;
// only the best constant is diagnosed in full (diagnose.cpp).

#include <vector>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/time_offset.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::gap {

struct ThermalTimeConstantChoice {
  double tau_s = 0.0;                 // the best of the grid and design.thermal_time_constant_s
  double heldout_mse = 0.0;           // at tau_s, per coordinate (m²)
  double heldout_mse_as_given = 0.0;  // at design.thermal_time_constant_s
};

// `data`: as the diagnosis fits it (decimated); `design`: the pass's
// settings; `selected`: its effects (thermal_drift among them); `sigma2`:
// the effects' prior's measurement variance (linear_fit.h's PriorWeights);
// `clock`: the pass's tracker time offset, removed from every design.
ThermalTimeConstantChoice ChooseThermalTimeConstant(const PlatformModel& model, const MeasurementData& data,
                                                    const DesignOptions& design, const std::vector<double>& grid_s,
                                                    const std::vector<Effect>& selected, double sigma2,
                                                    const TimeOffset& clock);

}  // namespace edsp::gap
