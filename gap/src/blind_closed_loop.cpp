#include "edsp/gap/blind_closed_loop.h"

#include <fstream>
#include <memory>
#include <stdexcept>
#include <utility>

#include "edsp/gap/closed_loop.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/pose.h"
#include "edsp/sim/sampled_runs.h"

namespace edsp::gap {

blind::ControllerCalibration BlindRigCalibration(const PlatformModel& model, const nlohmann::json& saved_model) {
  // Shared: the blind rig copies its setup, and the compensator's history
  // (play, loads) must run on through every step of a session.
  auto compensator = std::make_shared<calibration::LegCompensator>(
      model, calibration::ParseCalibration(saved_model.dump(), "the fit's model", model));
  return [compensator](double time_s, const blind::Vec6& pose, const blind::Vec6& velocity,
                       const blind::Vec6& acceleration, const blind::Vec6& command_m) {
    return blind::Vec6(compensator->Step(time_s, Pose::FromVector(pose), velocity, acceleration, command_m).command_m);
  };
}

blind::BlindRigSetup WithMotions(blind::BlindRigSetup setup, const PlatformModel& model,
                                 const PaperMotionOptions& paper, const std::vector<std::string>& motions) {
  setup.motions.clear();
  setup.sampled_motions.clear();
  for (const std::string& name : motions) {
    if (blind::IsBlindMotionName(name)) {
      setup.motions.push_back(name);
      continue;
    }
    for (const SampledRun& run : SampleRuns(model, {name}, paper, setup.control_rate_hz)) {
      blind::SampledMotion m{run.name, setup.control_rate_hz, {}, {}};
      for (const PoseSample& sample : run.samples) {
        m.poses.push_back(sample.pose);
        m.accelerations.push_back(sample.acceleration);
      }
      setup.motions.push_back(m.name);
      setup.sampled_motions.push_back(std::move(m));
    }
  }
  return setup;
}

BlindRun RunBlindRig(const blind::BlindRigSetup& setup, const blind::BlindScenario& rig, const std::string& csv_path) {
  BlindRun run;
  run.csv_path = csv_path;
  for (const std::string& name : setup.motions) run.duration_s += blind::MotionNamed(setup, name).duration_s();
  std::ofstream out(csv_path);
  out << blind::GenerateMeasurementCsv(setup, rig.effects, rig.tracker);
  if (!out) throw std::runtime_error(csv_path + ": cannot write the blind rig's measurement");
  return run;
}

MotionCheck MeasureBlindClosedLoop(const PlatformModel& model, blind::BlindRigSetup setup,
                                   const blind::BlindScenario& rig, const nlohmann::json& saved_model,
                                   const std::string& dir) {
  const std::string model_path = dir + "/model.json";
  std::ofstream(model_path) << saved_model.dump(2) << "\n";
  blind::BlindScenario held_out = rig;
  held_out.tracker.seed = rig.tracker.seed * 6364136223846793005ULL + 1442695040888963407ULL;
  setup.calibration = nullptr;
  const BlindRun without = RunBlindRig(setup, held_out, dir + "/closed_loop_without.csv");
  setup.calibration = BlindRigCalibration(model, saved_model);
  const BlindRun with = RunBlindRig(setup, held_out, dir + "/closed_loop_with.csv");
  return ScoreClosedLoop(model, without.csv_path, with.csv_path, saved_model, model_path);
}

}  // namespace edsp::gap
