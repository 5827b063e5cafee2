// [rig.effects] in a platform config: every effect and key read (a number
// for all legs or six), the nominal sections untouched, and errors that name
// the file, line and key for unknown effects, unknown keys and absurd values.
#include <algorithm>

#include <gtest/gtest.h>

#include "thrown_message.h"

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/leg_effects.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

const std::string kNominal = "[geometry]\npreset = \"huang2021\"\n";

std::string ErrorOf(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseRigEffects(text, "rig.toml"); }, "no error");
}

TEST(RigEffectsConfig, NoSectionMeansEveryEffectOffButTheDriveLoop) {
  const std::vector<calibration::Effect> only_servo = {calibration::Effect::kServoLag};
  EXPECT_EQ(EnabledEffects(ParseRigEffects(kNominal, "rig.toml")), only_servo);
  EXPECT_EQ(EnabledEffects(LoadRigEffects(SourcePath("config/huang2021.toml"))), only_servo);
  EXPECT_FALSE(ParseRigEffects(kNominal + "[rig.effects.servo_lag]\nenabled = false\n", "rig.toml").any());
}

TEST(RigEffectsConfig, EveryEffectIsRead) {
  const RigEffects e = ParseRigEffects(kNominal + R"(
[rig.effects.leg_offset]
offset_m = [1e-4, -5e-5, 0, 0, 0, 2e-5]
[rig.effects.joint_position]
base_m = [[1e-4, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, -2e-4]]
[rig.effects.passive_rotation]
pr_sign = -1
pr_lead_m = 0.012
[rig.effects.lead_error]
epsilon = 2e-4
[rig.effects.periodic_lead_error]
amplitude_m = 5e-6
phase_rad = [0, 1, 2, 3, 4, 5]
[rig.effects.backlash]
enabled = false
backlash_m = 3e-5
[rig.effects.servo_lag]
bandwidth_hz = 30
coulomb_N_m = 0.02
integral_time_s = 0.05
load_mass_kg = 300
[rig.effects.compliance]
stiffness_N_m = 2e7
mass_kg = 800
com_m = [0, 0, 0.1]
payload_kg = 200
payload_com_m = [0, 0, 0.6]
[rig.effects.thermal_drift]
heating_K_per_m = 1.5
time_constant_s = 900
)",
                                       "rig.toml");
  EXPECT_TRUE(e.leg_offset.enabled);
  EXPECT_EQ(e.leg_offset.offset_m[1], -5e-5);
  EXPECT_TRUE(e.joint_position.enabled);
  EXPECT_EQ(e.joint_position.base_m(0, 0), 1e-4);
  EXPECT_EQ(e.joint_position.base_m(2, 5), -2e-4);
  EXPECT_EQ(e.passive_rotation.pr_sign, -1);
  EXPECT_EQ(e.passive_rotation.pr_lead_m, 0.012);
  for (double eps : e.lead_error.epsilon) EXPECT_EQ(eps, 2e-4);  // one number: every leg
  EXPECT_EQ(e.periodic_lead_error.phase_rad[5], 5.0);
  EXPECT_FALSE(e.backlash.enabled);  // present but switched off
  EXPECT_EQ(e.backlash.backlash_m[0], 3e-5);
  EXPECT_TRUE(e.servo_lag.enabled);
  EXPECT_EQ(e.servo_lag.bandwidth_hz, 30.0);
  EXPECT_EQ(e.servo_lag.coulomb_N_m, 0.02);
  EXPECT_EQ(e.servo_lag.integral_time_s, 0.05);
  EXPECT_EQ(e.servo_lag.load_mass_kg, 300.0);
  EXPECT_EQ(e.servo_lag.screw_efficiency, 0.9);
  EXPECT_EQ(e.compliance.stiffness_N_m[3], 2e7);
  EXPECT_EQ(e.compliance.mass_kg, 800.0);
  EXPECT_EQ(e.compliance.com_m.z(), 0.1);
  EXPECT_EQ(e.compliance.total_mass_kg(), 1000.0);
  EXPECT_NEAR(e.compliance.total_com_m().z(), (800 * 0.1 + 200 * 0.6) / 1000.0, 1e-15);
  EXPECT_EQ(e.compliance.gravity_m_s2.z(), -9.81);  // default
  EXPECT_EQ(e.thermal_drift.heating_K_per_m, 1.5);
  EXPECT_EQ(e.thermal_drift.alpha_per_K, 11.7e-6);  // steel by default
  EXPECT_EQ(EnabledEffects(e).size(), 8u);          // backlash is off
  EXPECT_EQ(EnabledEffects(OnlyEffect(e, calibration::Effect::kCompliance)),
            std::vector<calibration::Effect>{calibration::Effect::kCompliance});
  // An effect that is off stays off alone.
  EXPECT_FALSE(OnlyEffect(e, calibration::Effect::kBacklash).any());
  const PlatformConfig truth = TrueConfig(Huang2021Config(), e);
  EXPECT_NEAR(truth.geometry.p_BoBi_B(0, 0) - Huang2021Config().geometry.p_BoBi_B(0, 0), 1e-4, 1e-15);
}

// The vocabulary is one table (rig_effects.cpp): every effect's table name
// parses into its own switch, is listed by EnabledEffects, stands alone
// with OnlyEffect, and is named among the known ones when a name is wrong.
TEST(RigEffectsConfig, EveryEffectIsParsedListedAndSwitchedAloneByItsName) {
  // Every effect of the shared vocabulary, in its order, so a new one is
  // tested here without an edit.
  std::vector<std::string> vocabulary;
  for (const calibration::Effect e : calibration::AllEffects()) vocabulary.emplace_back(calibration::EffectName(e));
  // The [rig.effects.NAME] sections users' configs rely on: one may be
  // added beside them, none renamed away.
  for (const char* contract : {"leg_offset", "joint_position", "passive_rotation", "lead_error", "periodic_lead_error",
                               "backlash", "servo_lag", "compliance", "thermal_drift", "structural_resonance"}) {
    EXPECT_EQ(std::count(vocabulary.begin(), vocabulary.end(), contract), 1) << contract;
  }
  auto section = [](const std::string& name, bool enabled) {
    std::string text = "[rig.effects." + name + "]\nenabled = " + (enabled ? "true" : "false") + "\n";
    if (name == "compliance") text += "stiffness_N_m = 2e7\nmass_kg = 800\n";  // no defaults: a rig's own
    return text;
  };
  std::string text = kNominal;
  for (const std::string& name : vocabulary) text += section(name, true);
  const RigEffects all = ParseRigEffects(text, "rig.toml");
  // Each once, in the rig's own order (kEffects).
  std::vector<std::string> enabled, expected = vocabulary;
  for (const calibration::Effect e : EnabledEffects(all)) enabled.emplace_back(calibration::EffectName(e));
  std::sort(enabled.begin(), enabled.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(enabled, expected);
  for (const std::string& name : vocabulary) {
    calibration::Effect effect;
    ASSERT_TRUE(calibration::ParseEffect(name, &effect)) << name;
    const RigEffects alone = OnlyEffect(all, effect);
    EXPECT_EQ(EnabledEffects(alone), std::vector<calibration::Effect>{effect});
    EXPECT_TRUE(alone.any()) << name;
    EXPECT_EQ(EnabledEffects(ParseRigEffects(kNominal + section(name, false), "rig.toml")).size(),
              name == "servo_lag" ? 0u : 1u)  // servo_lag is on unless switched off
        << name;
  }
  const std::string unknown = ErrorOf(kNominal + "[rig.effects.wobble]\nenabled = true\n");
  for (const std::string& name : vocabulary) EXPECT_NE(unknown.find(name), std::string::npos) << unknown;
}

// The rig's table is keyed by the kinematics' vocabulary (leg_effects.h):
// every effect the diagnosis can name, the benchmark can switch on alone
// on the rig, under the same name (rig_effects.cpp also asserts it).
TEST(RigEffectsConfig, EveryEffectOfTheVocabularyIsTheRigsByItsName) {
  const std::string known = ErrorOf(kNominal + "[rig.effects.wobble]\nenabled = true\n");
  for (calibration::Effect effect : calibration::AllEffects()) {
    const std::string name = calibration::EffectName(effect);
    const RigEffects on = ParseRigEffects(kNominal + "[rig.effects." + name + "]\nenabled = true\n" +
                                              (name == "compliance" ? "stiffness_N_m = 2e7\nmass_kg = 800\n" : ""),
                                          "rig.toml");
    EXPECT_EQ(EnabledEffects(OnlyEffect(on, effect)), std::vector<calibration::Effect>{effect}) << name;
    EXPECT_NE(known.find(name), std::string::npos) << known;
  }
}

TEST(RigEffectsConfig, ErrorsNameFileLineAndKey) {
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.wobble]\nx = 1\n").find("rig.toml:3: unknown effect [rig.effects.wobble]"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.backlash]\nbacklash = 1e-5\n")
                .find("unknown key [rig.effects.backlash] backlash"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.backlash]\nbacklash_m = 0.03\n").find("backlash_m = 0.03 (leg 1)"),
            std::string::npos);  // 30 mm: mm typed as m
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.lead_error]\nepsilon = [1, 2]\n").find("a number or an array of 6"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.lead_error]\nepsilon = 200\n").find("epsilon = 200"),
            std::string::npos);  // ppm typed as a fraction
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.passive_rotation]\npr_sign = 2\n").find("pr_sign = 2"), std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.servo_lag]\nbandwidth_hz = 1000\n").find("bandwidth_hz = 1000"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.servo_lag]\nintegral_time_s = 0.001\n").find("integral_time_s = 0.001"),
            std::string::npos);  // faster than the loop can take
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.servo_lag]\ncoulomb_N_m = 20\n").find("coulomb_N_m = 20"),
            std::string::npos);  // above the current limit
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.leg_offset]\noffset_m = nan\n").find("finite"), std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig]\nfoo = 1\n").find("unknown key [rig] foo"), std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.backlash]\nenabled = 1\n").find("true or false"), std::string::npos);
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.compliance]\nstiffness_N_m = 2e7\n").find("mass_kg = 0"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(kNominal + "[rig.effects.compliance]\nstiffness_N_m = 20\nmass_kg = 5\n").find("stiffness_N_m = 20"),
      std::string::npos);  // N/µm typed as N/m
  EXPECT_NE(ErrorOf(kNominal + "[rig.effects.thermal_drift]\nalpha_per_K = 11.7\n").find("alpha_per_K = 11.7"),
            std::string::npos);
}

}  // namespace
}  // namespace edsp
