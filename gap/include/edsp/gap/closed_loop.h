#pragma once
// The benchmark's closed-loop score: after a scenario is diagnosed, its rig
// runs motions the fit never saw twice, without and with the saved model
// applied by the kinematics (edsp-sim rig's offline stack, the rig keeping
// its own physics of every effect); point A's measured shrink is set beside
// the shrink the applied part of the model (AppliedModelJson) predicts
// offline from the first of the two runs.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/diagnosis/calibration_check.h"
#include "edsp/sim/offline_run.h"

namespace edsp::gap {

// `run`: the scenario's own run options (its compensation, tracker, frame),
// of which the motions and the output directory are replaced. The model is
// written to `dir`/model.json and applied as a user would: `identified`
// effects only. Throws what RunOffline or Evaluate throw.
MotionCheck MeasureClosedLoop(const PlatformModel& model, const std::string& config_path, const RigEffects& effects,
                              OfflineRunOptions run, const nlohmann::json& saved_model,
                              const std::vector<std::string>& motions, const std::string& dir);

// The score of the same motions measured without (`without_csv`) and with
// (`with_csv`) the model at `model_path` applied: point A's error measured
// in both, and the error the applied part of the model predicts from the
// first.
MotionCheck ScoreClosedLoop(const PlatformModel& model, const std::string& without_csv, const std::string& with_csv,
                            const nlohmann::json& saved_model, const std::string& model_path);

}  // namespace edsp::gap
