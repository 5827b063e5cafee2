// A calibration model read as the kinematics reads it: every wrong input
// named with the file and key, ambiguous effects held back unless asked,
// another platform's model refused; and its corrections against an
// independent computation (the inverse kinematics of the moved geometry).
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <gtest/gtest.h>

#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/config.h"
#include "platform_models.h"

namespace edsp::calibration {
namespace {

std::string Model(const std::string& effects, const std::string& extra = "") {
  return R"({"format": "edsp-gap-model/1", )" + extra + R"("effects": [)" + effects + "]}";
}

std::string Refusal(const std::string& text) {
  try {
    ParseCalibration(text, "m.json", test_support::Huang2021Model());
  } catch (const CalibrationError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Calibration, WrongModelsAreRefusedNamingFileAndKey) {
  EXPECT_NE(Refusal("{").find("m.json: not JSON"), std::string::npos);
  EXPECT_NE(Refusal(R"({"format": "x"})").find("\"format\""), std::string::npos);
  EXPECT_NE(Refusal(R"({"format": 1})").find("\"format\""), std::string::npos);
  EXPECT_NE(Refusal(Model(R"({"name": "leg_offset", "verdict": 3, "theta": [0,0,0,0,0,0]})")).find("\"verdict\""),
            std::string::npos);
  EXPECT_NE(Refusal(Model(R"({"name": "wobble", "theta": []})")).find("unknown effect \"wobble\""), std::string::npos);
  EXPECT_NE(Refusal(Model(R"({"name": "leg_offset", "theta": [1e-4]})")).find("needs 6 parameters, has 1"),
            std::string::npos);
  // 5 cm of leg offset is not a platform's calibration but a fit gone wrong.
  EXPECT_NE(Refusal(Model(R"({"name": "leg_offset", "theta": [0.05, 0, 0, 0, 0, 0]})")).find("theta[0] = 0.05"),
            std::string::npos);
  EXPECT_NE(Refusal(Model(R"({"name": "leg_offset", "theta": [0, 0, 0, 0, 0, "x"]})")).find("non-number"),
            std::string::npos);
  EXPECT_NE(
      Refusal(
          Model(R"({"name": "leg_offset", "theta": [0,0,0,0,0,0]}, {"name": "leg_offset", "theta": [0,0,0,0,0,0]})"))
          .find("listed twice"),
      std::string::npos);
  EXPECT_NE(Refusal(Model("", R"("thermal_time_constant_s": -1, )")).find("thermal_time_constant_s"),
            std::string::npos);
  EXPECT_NE(Refusal(Model("", R"("platform": "home_length_m=2,2,2,2,2,2", )")).find("another platform"),
            std::string::npos);
  const std::string mode = R"({"name": "structural_resonance", "theta": [0.3, 0.2, 0.1]})";
  EXPECT_NE(Refusal(Model(mode)).find("needs \"structural_mode_hz\" > 0"), std::string::npos);
  EXPECT_NE(Refusal(Model(mode, R"("structural_mode_hz": -5, )")).find("\"structural_mode_hz\" = -5"),
            std::string::npos);
  EXPECT_NE(Refusal(Model(mode, R"("structural_mode_hz": 5, "structural_mode_damping": "x", )"))
                .find("\"structural_mode_damping\" must be a number"),
            std::string::npos);
  EXPECT_EQ(Refusal(Model(mode, R"("structural_mode_hz": 5, )")), "accepted");
  EXPECT_EQ(Refusal(Model("")), "accepted");  // an empty model is valid
  EXPECT_EQ(Refusal(Model("", "\"platform\": \"" + PlatformFingerprint(test_support::Huang2021Model()) + "\", ")),
            "accepted");
}

TEST(Calibration, AmbiguousEffectsAreAppliedOnlyWhenAsked) {
  const std::string text = Model(R"({"name": "leg_offset", "verdict": "identified", "theta": [1e-4,0,0,0,0,0]},
                                     {"name": "lead_error", "verdict": "ambiguous", "theta": [1e-4,0,0,0,0,0]})");
  const CalibrationModel strict = ParseCalibration(text, "m.json", test_support::Huang2021Model());
  ASSERT_EQ(strict.applied.size(), 1u);
  EXPECT_EQ(strict.applied[0].effect, Effect::kLegOffset);
  EXPECT_NE(strict.Describe().find("not applied: lead_error (ambiguous)"), std::string::npos) << strict.Describe();
  EXPECT_EQ(ParseCalibration(text, "m.json", test_support::Huang2021Model(), true).applied.size(), 2u);
  EXPECT_EQ(strict.hash.size(), 16u);
  EXPECT_NE(strict.hash, ParseCalibration(text + " ", "m.json", test_support::Huang2021Model()).hash);
}

// A model whose entries say "apply" (edsp-gap's calibration set: the best
// predictor of held-out error, named or not) is applied as they say, an
// effect the diagnosis rejected as a name included; ambiguous ones are
// still added when asked.
TEST(Calibration, EntriesThatSayApplyAreAppliedAsTheySay) {
  const std::string text =
      Model(R"({"name": "leg_offset", "verdict": "identified", "theta": [1e-4,0,0,0,0,0], "apply": false},
                                     {"name": "lead_error", "verdict": "ambiguous", "theta": [1e-4,0,0,0,0,0], "apply": true},
                                     {"name": "backlash", "verdict": "rejected", "theta": [1e-5,1e-5,1e-5,1e-5,1e-5,1e-5], "apply": true},
                                     {"name": "compliance", "verdict": "ambiguous", "theta": [1e-8,0,0,0,0,0,0,0,0], "apply": false})");
  const auto names = [](const CalibrationModel& m) {
    std::vector<Effect> out;
    for (const CalibratedEffect& e : m.applied) out.push_back(e.effect);
    return out;
  };
  const CalibrationModel as_saved = ParseCalibration(text, "m.json", test_support::Huang2021Model());
  EXPECT_EQ(names(as_saved), (std::vector<Effect>{Effect::kLeadError, Effect::kBacklash}));
  EXPECT_NE(as_saved.Describe().find("not applied: leg_offset (identified), compliance (ambiguous)"), std::string::npos)
      << as_saved.Describe();
  EXPECT_EQ(names(ParseCalibration(text, "m.json", test_support::Huang2021Model(), true)),
            (std::vector<Effect>{Effect::kLeadError, Effect::kBacklash, Effect::kCompliance}));
  // Without "apply", a rejected entry is not applied; a wrong "apply" is named.
  EXPECT_TRUE(ParseCalibration(Model(R"({"name": "backlash", "verdict": "rejected", "theta": [0,0,0,0,0,0]})"),
                               "m.json", test_support::Huang2021Model())
                  .applied.empty());
  EXPECT_NE(
      Refusal(Model(R"({"name": "leg_offset", "theta": [0,0,0,0,0,0], "apply": "yes"})")).find("\"apply\" must be"),
      std::string::npos);
  EXPECT_NE(Refusal(Model(R"({"name": "leg_offset", "verdict": "maybe", "theta": [0,0,0,0,0,0]})")).find("\"maybe\""),
            std::string::npos);
  // A named effect the set leaves out commands nothing: beyond a platform's
  // limits it is not applied, not a reason to refuse the set; applied, it is.
  const std::string absurd = R"({"name": "leg_offset", "theta": [0.05, 0, 0, 0, 0, 0], "apply": )";
  EXPECT_EQ(Refusal(Model(absurd + "false}")), "accepted");
  EXPECT_NE(Refusal(Model(absurd + "true}")).find("theta[0] = 0.05"), std::string::npos);
}

// Joint centres moved: the command correction is what the inverse
// kinematics of the moved geometry says the legs must change by (to first
// order in the µm-sized move), at poses away from home.
TEST(Calibration, JointCentreCorrectionIsTheMovedGeometrysInverseKinematics) {
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(36);
  for (int k = 0; k < 36; ++k) theta(k) = 1e-4 * std::sin(1.0 + 0.7 * k);
  CalibrationModel m;
  m.applied.push_back({Effect::kJointPosition, theta, Verdict::kIdentified});
  PlatformConfig moved = Huang2021Config();
  for (int i = 0; i < 6; ++i) {
    for (int a = 0; a < 3; ++a) {
      moved.geometry.p_BoBi_B(a, i) += theta(3 * i + a);
      moved.geometry.p_MoPi_M(a, i) += theta(18 + 3 * i + a);
    }
  }
  const PlatformModel nominal = test_support::Huang2021Model(), truth(moved);
  const Vector6 home = nominal.home_pose().ToVector();
  for (const Vector6& dq : {Vector6((Vector6() << 0.1, -0.05, 0.2, 0.05, -0.1, 0.3).finished()),
                            Vector6((Vector6() << -0.2, 0.1, -0.1, 0.0, 0.1, -0.2).finished())}) {
    const Pose pose = Pose::FromVector(home + dq);
    const Vector6 command = nominal.Solve(pose).length_m;
    LegCompensator compensator(nominal, m);  // its first step: no rate limit to start from
    const Vector6 correction = compensator.Step(0.0, pose, Vector6::Zero(), Vector6::Zero(), command).command_m;
    // The nominal model must reach `pose` with the moved geometry's lengths:
    // the command subtracts (nominal − moved) IK length.
    const Vector6 expected = nominal.Solve(pose).length_m - truth.Solve(pose).length_m;
    EXPECT_LT((correction - expected).cwiseAbs().maxCoeff(), 1e-8) << correction.transpose() << "\n"
                                                                   << expected.transpose();
    EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1e-5);  // a correction worth checking
  }
}

// A setpoint velocity that jumps (a CSV trajectory's rows) with a servo-lag
// model: the feed-forward follows, but never faster than 0.05 m/s, so the
// command cannot step; once the rate is steady the full correction is there.
TEST(Calibration, FeedForwardOfAJumpingVelocityNeverSteps) {
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(13);
  theta.head(6).setConstant(0.013);  // a 13 ms lag
  CalibrationModel m;
  m.applied.push_back({Effect::kServoLag, theta, Verdict::kIdentified});
  const PlatformModel nominal = test_support::Huang2021Model();
  LegCompensator compensator(nominal, m);
  const Pose home = nominal.home_pose();
  const Vector6 command = nominal.Solve(home).length_m;
  Vector6 velocity = Vector6::Zero();
  Vector6 last = compensator.Step(0.0, home, velocity, Vector6::Zero(), command).command_m;
  velocity(2) = 0.1;  // 0.1 m/s up at once: 1.3 mm of lag to feed forward
  double largest_step = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const Vector6 c = compensator.Step(k * 1e-3, home, velocity, Vector6::Zero(), command).command_m;
    largest_step = std::max(largest_step, (c - last).cwiseAbs().maxCoeff());
    last = c;
  }
  EXPECT_LE(largest_step, LegCompensator::kMaxCorrectionRate_m_s * 1e-3 * (1 + 1e-9));
  const Vector6 full = -0.013 * (nominal.LengthJacobian(home) - nominal.PrLengthErrorJacobian(home)) * velocity;
  EXPECT_LT((last - full).cwiseAbs().maxCoeff(), 1e-9) << last.transpose() << "\n" << full.transpose();
  EXPECT_GT(full.cwiseAbs().maxCoeff(), 1e-3);
}

// A periodic lead error beside a 300 µm leg offset, held at one pose: the
// correction settles where the corrected command puts the screw,
// c = θ_offset + a·sin φ + b·(cos φ − 1), φ = 2π·(stroke − c)/lead, solved
// here by fixed-point iteration on that formula, not at the nominal
// stroke (there it would differ by micrometres).
TEST(Calibration, APeriodicErrorIsCorrectedWhereTheCorrectedCommandTurnsTheScrew) {
  const PlatformModel nominal = test_support::Huang2021Model();
  Eigen::VectorXd periodic(12);
  for (int i = 0; i < 6; ++i) periodic(2 * i) = 10e-6, periodic(2 * i + 1) = -6e-6;
  CalibrationModel m;
  m.applied.push_back({Effect::kLegOffset, Eigen::VectorXd::Constant(6, 300e-6), Verdict::kIdentified});
  m.applied.push_back({Effect::kPeriodicLeadError, periodic, Verdict::kIdentified});
  LegCompensator compensator(nominal, m);
  Pose pose = nominal.home_pose();
  pose.p_BoMo_B.z() += 0.043;
  const Vector6 command = nominal.Solve(pose).length_m - nominal.PrLengthError(nominal.Solve(pose), PrMode::kSigned);
  Vector6 c = Vector6::Zero();
  for (int k = 0; k < 40; ++k)
    c = compensator.Step(k * 1e-3, pose, Vector6::Zero(), Vector6::Zero(), command).command_m;
  const double lead = nominal.config().drive.lead_m;
  const auto at = [&](const Vector6& stroke) {
    Vector6 out;
    for (int i = 0; i < 6; ++i) {
      const double phi = 2.0 * M_PI * stroke(i) / lead;
      out(i) = 300e-6 + 10e-6 * std::sin(phi) - 6e-6 * (std::cos(phi) - 1.0);
    }
    return out;
  };
  const Vector6 stroke = command - nominal.home_length_m();
  Vector6 expected = at(stroke);
  for (int k = 0; k < 20; ++k) expected = at(stroke - expected);
  EXPECT_LT((c - expected).cwiseAbs().maxCoeff(), 1e-10) << c.transpose() << "\n" << expected.transpose();
  EXPECT_GT((at(stroke) - expected).cwiseAbs().maxCoeff(), 1e-6);  // the nominal stroke's would fail above
}

// The verdicts are typed; their names are the model file's (interfaces.md
// §4), and which entries a calibration applies follows from them.
TEST(Calibration, VerdictsReadAndPrintTheModelFilesNames) {
  for (const auto& [verdict, name] :
       {std::pair{Verdict::kIdentified, "identified"}, std::pair{Verdict::kAmbiguous, "ambiguous"},
        std::pair{Verdict::kRejected, "rejected"}}) {
    EXPECT_STREQ(VerdictName(verdict), name);
    EXPECT_EQ(VerdictFromName(name), verdict) << name;
  }
  EXPECT_EQ(VerdictFromName("Identified"), std::nullopt);
  EXPECT_EQ(VerdictFromName(""), std::nullopt);
  // Without "apply": identified only, ambiguous when asked; "apply" decides when given.
  EXPECT_TRUE(AppliesEntry(Verdict::kIdentified, false, false, false));
  EXPECT_FALSE(AppliesEntry(Verdict::kAmbiguous, false, false, false));
  EXPECT_TRUE(AppliesEntry(Verdict::kAmbiguous, false, false, true));
  EXPECT_FALSE(AppliesEntry(Verdict::kRejected, false, false, true));
  EXPECT_TRUE(AppliesEntry(Verdict::kRejected, true, true, false));
  EXPECT_FALSE(AppliesEntry(Verdict::kIdentified, true, false, false));
}

}  // namespace
}  // namespace edsp::calibration
