// What a prediction must use to be set beside a calibrated measurement: the
// effects the kinematics applies (kinematics/calibration.h), checked here
// against the kinematics' own reading of the same model.
#include <algorithm>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/config.h"

namespace edsp::gap {
namespace {

const nlohmann::json kModel = nlohmann::json::parse(R"({"format": "edsp-gap-model/1", "effects": [
    {"name": "leg_offset", "verdict": "identified", "theta": [1e-5, 0, 0, 0, 0, 0]},
    {"name": "lead_error", "verdict": "ambiguous", "theta": [1e-5, 0, 0, 0, 0, 0]},
    {"name": "backlash", "theta": [1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5]}]})");

std::vector<std::string> Names(const nlohmann::json& model) {
  std::vector<std::string> names;
  for (const auto& e : model["effects"]) names.push_back(e["name"]);
  return names;
}

std::vector<std::string> KinematicsApplies(bool apply_ambiguous) {
  const calibration::CalibrationModel m = calibration::ParseCalibration(
      kModel.dump(), "m.json", PlatformModel(Huang2021Config()), apply_ambiguous);
  std::vector<std::string> names;
  for (const auto& e : m.applied) names.push_back(calibration::EffectName(e.effect));
  return names;
}

TEST(AppliedModel, TheEffectsThePredictionUsesAreThoseTheKinematicsApplies) {
  for (bool ambiguous : {false, true}) {
    std::vector<std::string> predicted = Names(AppliedModelJson(kModel, ambiguous)), applied = KinematicsApplies(ambiguous);
    std::sort(predicted.begin(), predicted.end());
    std::sort(applied.begin(), applied.end());
    EXPECT_EQ(predicted, applied) << "apply_ambiguous " << ambiguous;
  }
  EXPECT_EQ(Names(AppliedModelJson(kModel, false)), (std::vector<std::string>{"leg_offset", "backlash"}));
}

}  // namespace
}  // namespace edsp::gap
