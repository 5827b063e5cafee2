// What a prediction must use to be set beside a calibrated measurement: the
// effects the kinematics applies (kinematics/calibration.h), checked here
// against the kinematics' own reading of the same model.
#include <algorithm>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "thrown_message.h"

#include "edsp/diagnosis/report.h"
#include "edsp/diagnosis/saved_model.h"
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

std::vector<std::string> KinematicsAppliesOf(const nlohmann::json& model, bool apply_ambiguous) {
  const calibration::CalibrationModel m =
      calibration::ParseCalibration(model.dump(), "m.json", PlatformModel(Huang2021Config()), apply_ambiguous);
  std::vector<std::string> names;
  for (const auto& e : m.applied) names.push_back(calibration::EffectName(e.effect));
  return names;
}

std::vector<std::string> KinematicsApplies(bool apply_ambiguous) {
  return KinematicsAppliesOf(kModel, apply_ambiguous);
}

TEST(AppliedModel, TheEffectsThePredictionUsesAreThoseTheKinematicsApplies) {
  for (bool ambiguous : {false, true}) {
    std::vector<std::string> predicted = Names(AppliedModelJson(kModel, ambiguous)),
                             applied = KinematicsApplies(ambiguous);
    std::sort(predicted.begin(), predicted.end());
    std::sort(applied.begin(), applied.end());
    EXPECT_EQ(predicted, applied) << "apply_ambiguous " << ambiguous;
  }
  EXPECT_EQ(Names(AppliedModelJson(kModel, false)), (std::vector<std::string>{"leg_offset", "backlash"}));
}

// A calibration set saved by edsp-gap: its entries say "apply".
TEST(AppliedModel, EntriesThatSayApplyAreThoseThePredictionUses) {
  nlohmann::json model = kModel;
  model["effects"][0]["apply"] = false;
  model["effects"][1]["apply"] = true;
  model["effects"].push_back(
      {{"name", "compliance"}, {"verdict", "rejected"}, {"theta", {1e-8, 0, 0, 0, 0, 0, 0, 0, 0}}, {"apply", true}});
  model["effects"][2]["apply"] = false;
  EXPECT_EQ(Names(AppliedModelJson(model, false)), (std::vector<std::string>{"lead_error", "compliance"}));
  const calibration::CalibrationModel m =
      calibration::ParseCalibration(model.dump(), "m.json", PlatformModel(Huang2021Config()), false);
  ASSERT_EQ(m.applied.size(), 2u);
  EXPECT_EQ(m.applied[0].effect, calibration::Effect::kLeadError);
  EXPECT_EQ(m.applied[1].effect, calibration::Effect::kCompliance);
  // Asked for the ambiguous ones too, the prediction's reader keeps what the
  // kinematics then applies, an ambiguous entry the set left out included.
  model["effects"][1]["apply"] = false;
  const std::vector<SavedEffect> read = SavedAppliedEffects(AppliedModelJson(model, true), DesignOptions{}, "m.json");
  std::vector<std::string> names;
  for (const SavedEffect& e : read) names.push_back(EffectName(e.effect));
  EXPECT_EQ(names, (std::vector<std::string>{"lead_error", "compliance"}));
  EXPECT_EQ(KinematicsAppliesOf(model, true), names);
}

// A verdict that is none of the three: the kinematics refuses the file, and
// so does the prediction's reader, naming the file, the effect and the
// value; the part the kinematics would apply keeps such an entry only as
// its "apply" says, as it keeps a rejected one.
TEST(AppliedModel, AVerdictThatIsNoneOfTheThreeIsNamed) {
  nlohmann::json model = kModel;
  model["effects"][0]["verdict"] = "maybe";
  EXPECT_EQ(Names(AppliedModelJson(model, false)), (std::vector<std::string>{"backlash"}));
  model["effects"][0]["apply"] = true;
  EXPECT_EQ(Names(AppliedModelJson(model, false)), (std::vector<std::string>{"leg_offset", "backlash"}));
  const std::string error = test_support::ThrownMessage<MeasurementError>(
      [&] { SavedAppliedEffects(model, DesignOptions{}, "m.json"); }, "accepted");
  EXPECT_NE(error.find("m.json: effect leg_offset \"verdict\" \"maybe\""), std::string::npos) << error;
  model["effects"][0]["verdict"] = 3;
  EXPECT_NE(test_support::ThrownMessage<MeasurementError>(
                [&] { SavedAppliedEffects(model, DesignOptions{}, "m.json"); }, "accepted")
                .find("\"verdict\" 3"),
            std::string::npos);
  model["effects"][0].erase("verdict");  // saved before verdicts: identified
  EXPECT_EQ(SavedAppliedEffects(model, DesignOptions{}, "m.json").front().verdict, Verdict::kIdentified);
}

}  // namespace
}  // namespace edsp::gap
