#include "edsp/gap/closed_loop.h"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp::gap {

MotionCheck MeasureClosedLoop(const PlatformModel& model, const std::string& config_path, const RigEffects& effects,
                              OfflineRunOptions run, const nlohmann::json& saved_model,
                              const std::vector<std::string>& motions, const std::string& dir) {
  const std::string model_path = dir + "/model.json";
  std::ofstream(model_path) << saved_model.dump(2) << "\n";
  run.motions = motions;
  run.calibration_path.clear();
  run.apply_ambiguous = false;
  run.out_dir = dir + "/closed_loop_without";
  const OfflineRunResult without = RunOffline(config_path, effects, run);
  run.calibration_path = model_path;
  run.out_dir = dir + "/closed_loop_with";
  const OfflineRunResult with = RunOffline(config_path, effects, run);
  // A run with faults (a command refused: a calibration whose start the
  // bridge took for a jump, say) measured a platform that stood, not the model.
  for (const OfflineRunResult* r : {&without, &with}) {
    if (r->faults > 0) {
      throw std::runtime_error(fmt::format("{}: {} fault(s) (EDSP_FAULT in {}): not a measurement of the {}",
                                           r == &with ? "the run with the calibration" : "the run without it",
                                           r->faults, r->log_path, r == &with ? "calibration" : "rig"));
    }
  }
  return ScoreClosedLoop(model, without.csv_path, with.csv_path, saved_model, model_path);
}

MotionCheck ScoreClosedLoop(const PlatformModel& model, const std::string& without_csv, const std::string& with_csv,
                            const nlohmann::json& saved_model, const std::string& model_path) {
  // Predicted from what the kinematics applies, not the whole model: the
  // two must compare like with like.
  const Evaluation predicted =
      Evaluate(model, LoadMeasurement(without_csv), AppliedModelJson(saved_model, false), model_path);
  const Evaluation measured = Evaluate(model, LoadMeasurement(with_csv), EmptyModelJson(), "no model");
  return CheckCalibration(predicted, measured, true).overall;
}

}  // namespace edsp::gap
