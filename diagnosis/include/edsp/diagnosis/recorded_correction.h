#pragma once
// Data recorded with a calibration in force, read against the nominal model
// or against that calibration. The kinematics took the calibration's
// correction c off every command (leg_corr_*_m, §3), so the platform landed
// where the calibration put it: the residual against the commanded pose is
// what the calibration leaves. Against the nominal model the data is read as
// if the nominal kinematics had commanded it: c back on the command (and the
// encoders), and point A moved by what c moved it, R·G·c (G = ∂A/∂l at the
// commanded pose, R the tracker frame's rotation estimated on the data as
// recorded; first order in c: the second-order part is about 1 µm for a
// millimetre on every leg, 0.1 µm for the 0.3 mm a real calibration
// corrects). A diagnosis of that names and sizes the rig's whole effects, so
// the model it saves replaces the first calibration rather than adding to it.

#include <string>

#include "edsp/diagnosis/measurement_data.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::gap {

enum class Against { kNominal, kCalibration };

const char* AgainstName(Against against);  // "nominal", "calibration"

// Whether any row carries a non-zero correction.
bool CarriesACorrection(const MeasurementData& data);

// `data` as the nominal model would have commanded it: every row's
// correction moved into its command, encoders and point A, then zero.
// `shift_rms_m` (may be null): the RMS over rows of A's move, what the
// recorded calibration did at A. Throws MeasurementError naming the run and
// time of a commanded pose the model cannot solve.
MeasurementData AsCommandedNominally(const PlatformModel& model, const MeasurementData& data,
                                     double* shift_rms_m = nullptr);

}  // namespace edsp::gap
