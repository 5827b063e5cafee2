#pragma once
// edsp's calibration closed on the independently written rig (blindrig/):
// the blind rig runs the motions with its own kinematics and physics, and
// edsp's LegCompensator takes its correction off each of the blind
// controller's commands, one control step at a time, as the kinematics node
// does. So a calibration is scored on a rig whose physics share no code with
// the model that made it (docs/calibration.md).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_rig.h"
#include "edsp/diagnosis/calibration_check.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/paper_motions.h"

namespace edsp::gap {

// The blind controller's correction for a saved model: the entries the
// kinematics applies (calibration::AppliesEntry), as `edsp-kinematics
// --calibration` applies them. Throws calibration::CalibrationError for a
// model the kinematics refuses.
blind::ControllerCalibration BlindRigCalibration(const PlatformModel& model, const nlohmann::json& saved_model);

// `setup` to run `motions`: the blind rig's own by name (Lz, M3, …), the
// others planned by edsp's planner with `paper` (the designed "calibration"
// set: its runs cal1, cal2, …) and sampled at the rig's control rate.
// Throws std::invalid_argument for a motion neither knows.
blind::BlindRigSetup WithMotions(blind::BlindRigSetup setup, const PlatformModel& model,
                                 const PaperMotionOptions& paper, const std::vector<std::string>& motions);

struct BlindRun {
  std::string csv_path;
  double duration_s = 0.0;  // the motions' length, as run
};

// The measurement CSV of the setup's motions on the blind rig, written to
// `csv_path`. Throws what GenerateMeasurementCsv throws, or if the file
// cannot be written.
BlindRun RunBlindRig(const blind::BlindRigSetup& setup, const blind::BlindScenario& rig, const std::string& csv_path);

// As MeasureClosedLoop (closed_loop.h) on the blind rig: the setup's motions
// run without and with the saved model, measured with another draw of the
// tracker's noise than the fit's; the model is written to `dir`/model.json.
MotionCheck MeasureBlindClosedLoop(const PlatformModel& model, blind::BlindRigSetup setup,
                                   const blind::BlindScenario& rig, const nlohmann::json& saved_model,
                                   const std::string& dir);

}  // namespace edsp::gap
