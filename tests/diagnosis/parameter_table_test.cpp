// report.md's parameter tables: each θ (SI, as fitted) in the unit a rig
// team quotes, in the right leg's row and column, with its σ. The expected
// cells are worked out by hand from the basis' units (leg_error_model.cpp).
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "edsp/diagnosis/parameter_table.h"
#include "edsp/diagnosis/report.h"

namespace edsp::gap {
namespace {

EffectResult Fitted(Effect effect) {
  EffectResult r;
  r.effect = effect;
  r.verdict = Verdict::kIdentified;
  r.theta = Eigen::VectorXd::Zero(ParameterCount(effect));
  r.sigma = Eigen::VectorXd::Zero(ParameterCount(effect));
  return r;
}

// The row of leg `leg` (1-based) in a per-leg table.
std::string Row(const std::string& table, int leg) {
  const std::string start = "\n| " + std::to_string(leg) + " |";
  const std::size_t at = table.find(start);
  if (at == std::string::npos) return "";
  return table.substr(at + 1, table.find('\n', at + 1) - at - 1);
}

// An effect that gains nothing held out reads 0.0%, not -0.0%; a real
// loss keeps its sign.
TEST(ReportText, PercentNeverSaysMinusZero) {
  EXPECT_EQ(Percent(-1e-6), "0.0%");
  EXPECT_EQ(Percent(-0.0004), "0.0%");
  EXPECT_EQ(Percent(-0.003), "-0.3%");
  EXPECT_EQ(Percent(0.994), "99.4%");
}

TEST(ParameterTable, ValueWithSigmaRoundsBothAndOmitsAMissingSigma) {
  EXPECT_EQ(ValueWithSigma(12.345, 0.44, 1), "12.3 ± 0.4");
  EXPECT_EQ(ValueWithSigma(12.345, std::nan(""), 1), "12.3");
  EXPECT_EQ(ValueWithSigma(12.345, 0.0, 2), "12.35");
  EXPECT_EQ(ValueWithSigma(std::nan(""), 0.1, 1), "–");
}

TEST(ParameterTable, LeadErrorIsInPpmPerLeg) {
  EffectResult r = Fitted(Effect::kLeadError);
  r.theta(2) = 12.3e-6;
  r.sigma(2) = 0.4e-6;
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_NE(t.find("lead error (ppm)"), std::string::npos) << t;
  EXPECT_EQ(Row(t, 3), "| 3 | 12.3 ± 0.4 |") << t;
  EXPECT_EQ(Row(t, 1), "| 1 | 0.0 |") << t;
}

TEST(ParameterTable, JointCentresPutEachCoordinateInItsLegAndColumn) {
  EffectResult r = Fitted(Effect::kJointPosition);
  r.theta(3 * 1 + 0) = 25e-6;        // base x of leg 2
  r.theta(18 + 3 * 4 + 2) = -40e-6;  // platform z of leg 5
  r.sigma(18 + 3 * 4 + 2) = 3e-6;
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_EQ(Row(t, 2), "| 2 | 25.0 | 0.0 | 0.0 | 0.0 | 0.0 | 0.0 |") << t;
  EXPECT_EQ(Row(t, 5), "| 5 | 0.0 | 0.0 | 0.0 | 0.0 | 0.0 | -40.0 ± 3.0 |") << t;
}

TEST(ParameterTable, ServoLagInMillisecondsAndTheJerkTermOnce) {
  EffectResult r = Fitted(Effect::kServoLag);
  r.theta(0) = 4e-3;      // s
  r.theta(6 + 5) = 2e-5;  // s², leg 6
  r.theta(12) = 6e-8;     // s³
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_EQ(Row(t, 1), "| 1 | 4.00 | 0.00 |") << t;
  EXPECT_EQ(Row(t, 6), "| 6 | 0.00 | 20.00 |") << t;
  EXPECT_NE(t.find("| jerk lag, all legs | 60.0 | ms³ |"), std::string::npos) << t;
}

TEST(ParameterTable, ComplianceIsTheShorteningPerGOfLoad) {
  EffectResult r = Fitted(Effect::kCompliance);
  r.theta(0) = 4e-5;  // m/k in s²: 4e-5 s² × 9.80665 m/s² = 392.3 µm at 1 g
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_EQ(Row(t, 1), "| 1 | 392.27 |") << t;
}

TEST(ParameterTable, PassiveRotationScalesReadAsFactors) {
  EffectResult r = Fitted(Effect::kPassiveRotation);
  r.theta << 0.05, -0.25;  // the applied compensation's scale is 1 + θ1
  r.sigma << 0.002, 0.01;
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_NE(t.find("| 0.050 ± 0.002 | × |"), std::string::npos) << t;
  EXPECT_NE(t.find("| 0.750 ± 0.010 | × |"), std::string::npos) << t;
}

TEST(ParameterTable, ThermalDriftPerMetreOfTravelAndPerHourUnderPower) {
  EffectResult r = Fitted(Effect::kThermalDrift);
  r.theta(0) = 7e-6;  // m per m of travel
  r.theta(2) = 1e-9;  // m per s powered: 3.6 µm per hour
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_NE(t.find("| with recent travel | 7.00 | µm per m of travel |"), std::string::npos) << t;
  EXPECT_NE(t.find("| with time under power | 3.60 | µm per hour |"), std::string::npos) << t;
}

TEST(ParameterTable, PeriodicLeadErrorAsAmplitudeAndPhase) {
  EffectResult r = Fitted(Effect::kPeriodicLeadError);
  r.theta(2) = 3e-6;  // leg 2: sin part
  r.theta(3) = 4e-6;  //        cos part
  const std::string t = ParameterTableMarkdown(r);
  EXPECT_EQ(Row(t, 2), "| 2 | 5.0 | 53 |") << t;
}

// Verdicts, conclusions and how the calibration was chosen are typed; the
// report keeps their names (interfaces.md §4), which users' scripts read:
// `ambiguous_with` lists the effects, then `unknown`; the ranking holds
// `unknown` after the selected effects, or `none` first.
TEST(ReportText, TypedVerdictsAndConclusionsKeepTheReportsNames) {
  Diagnosis d;
  d.conclusion = Conclusion::kEffectsAndUnknown;
  d.selected = {Effect::kServoLag};
  EffectResult lag = Fitted(Effect::kServoLag), compliance = Fitted(Effect::kCompliance),
               offset = Fitted(Effect::kLegOffset);
  lag.verdict = compliance.verdict = Verdict::kAmbiguous;
  lag.ambiguous_with = {Effect::kCompliance};
  lag.ambiguous_with_unknown = true;
  compliance.ambiguous_with = {Effect::kServoLag};
  offset.verdict = Verdict::kRejected;
  d.effects = {lag, compliance, offset};
  d.calibration.chosen_by = ChosenBy::kForward;
  const nlohmann::json j = ToJson(d);
  EXPECT_EQ(j["conclusion"], "effects+unknown");
  EXPECT_EQ(j["calibration"]["chosen_by"], "forward");
  ASSERT_EQ(j["effects"].size(), 4u) << j["effects"].dump();
  EXPECT_EQ(j["effects"][0]["name"], "servo_lag");
  EXPECT_EQ(j["effects"][0]["verdict"], "ambiguous");
  EXPECT_EQ(j["effects"][0]["ambiguous_with"], nlohmann::json({"compliance", "unknown"}));
  EXPECT_EQ(j["effects"][1]["name"], "unknown");
  EXPECT_EQ(j["effects"][1]["verdict"], "identified");
  EXPECT_EQ(j["effects"][2]["ambiguous_with"], nlohmann::json({"servo_lag"}));
  EXPECT_EQ(j["effects"][3]["verdict"], "rejected");
  EXPECT_FALSE(j["effects"][3].contains("ambiguous_with"));

  d.conclusion = Conclusion::kNone;
  d.selected.clear();
  d.effects = {offset};
  const nlohmann::json none = ToJson(d);
  EXPECT_EQ(none["conclusion"], "none");
  ASSERT_EQ(none["effects"].size(), 2u) << none["effects"].dump();
  EXPECT_EQ(none["effects"][0]["name"], "none");
  EXPECT_EQ(none["effects"][0]["verdict"], "identified");

  d.conclusion = Conclusion::kUnknown;
  const nlohmann::json unknown = ToJson(d);
  ASSERT_EQ(unknown["effects"].size(), 2u) << unknown["effects"].dump();
  EXPECT_EQ(unknown["effects"][0]["name"], "unknown");
}

TEST(ReportText, ConclusionsReadAndPrintTheReportsNames) {
  for (const auto& [conclusion, name] :
       {std::pair{Conclusion::kEffects, "effects"}, std::pair{Conclusion::kNone, "none"},
        std::pair{Conclusion::kUnknown, "unknown"}, std::pair{Conclusion::kEffectsAndUnknown, "effects+unknown"}}) {
    EXPECT_STREQ(ConclusionName(conclusion), name);
  }
  EXPECT_EQ(WithUnknown(Conclusion::kEffects), Conclusion::kEffectsAndUnknown);
  EXPECT_EQ(WithUnknown(Conclusion::kNone), Conclusion::kUnknown);
  EXPECT_EQ(WithUnknown(Conclusion::kUnknown), Conclusion::kUnknown);
  EXPECT_TRUE(NamesUnknown(Conclusion::kEffectsAndUnknown));
  EXPECT_FALSE(NamesUnknown(Conclusion::kEffects));
  EXPECT_STREQ(ChosenByName(ChosenBy::kIdentified), "identified");
  EXPECT_STREQ(ChosenByName(ChosenBy::kBackward), "backward");
}

TEST(ParameterTable, AnEffectWithoutParametersHasNoTable) {
  EffectResult r;
  r.effect = Effect::kBacklash;
  EXPECT_EQ(ParameterTableMarkdown(r), "");
}

}  // namespace
}  // namespace edsp::gap
