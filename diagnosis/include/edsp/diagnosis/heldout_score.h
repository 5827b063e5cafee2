#pragma once
// The held-out error of a fixed set of effects: the tracker frame (and the
// design's nuisance) with those effects' columns, each held-out fold
// predicted by a fit on the others, as selection scores its candidates
// (linear_fit.h's HeldOutMse). What the searches over the bases' non-linear
// parameters compare (thermal_time_constant_fit.h), and what the benchmark
// asks of a miss: would the true effects have predicted the held-out runs
// better than the ones found, or can the data not tell them apart?

#include <vector>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/time_offset.h"

namespace edsp::gap {

// Per coordinate (m²). `data`: as the diagnosis fits it (decimated);
// `sigma2`: the effects' prior's measurement variance (PriorWeights);
// `clock`: the tracker's time offset, removed when applied.
double HeldOutMseOf(const PlatformModel& model, const MeasurementData& data, const DesignOptions& design,
                    const std::vector<Effect>& effects, double sigma2, const TimeOffset& clock);

// Held-out RMS at A (as Diagnosis::holdout_after) of `effects` on `data`,
// with the bases' settings, the clock and the prior `d` found. Effects `d`
// did not select get their non-linear parameters searched as the diagnosis
// would have: a structural_resonance the mode that predicts the held-out
// runs best beside the others (structural_mode_fit.h), a thermal_drift its
// time constant from the grid (thermal_time_constant_fit.h). A backlash `d`
// did not find keeps the design's play width (its first guess).
double HeldOutRmsOf(const PlatformModel& model, const MeasurementData& data, const DiagnoseOptions& options,
                    const Diagnosis& d, const std::vector<Effect>& effects);

}  // namespace edsp::gap
