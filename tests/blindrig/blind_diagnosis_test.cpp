// edsp-gap on data from the independently written rig: what it names must be
// what the blind rig holds, and what lies outside its vocabulary must come
// back `unknown`, however small beside the tracker's noise.
#include <algorithm>

#include <gtest/gtest.h>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/diagnosis/diagnose.h"

namespace edsp::blind {
namespace {

gap::Diagnosis DiagnoseBlind(const BlindEffects& effects, double noise_m = 10e-6, double rate_hz = 100.0) {
  BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  setup.motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
  TrackerOptions tracker;
  tracker.rate_hz = rate_hz;
  tracker.noise_m = noise_m;
  tracker.seed = 5;
  const gap::MeasurementData data = gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, effects, tracker), "blind");
  return gap::Diagnose(PlatformModel(Huang2021Config()), data);
}

std::vector<std::string> Identified(const gap::Diagnosis& d) {
  std::vector<std::string> names;
  for (const gap::EffectResult& r : d.effects) {
    if (r.verdict == "identified") names.push_back(gap::EffectName(r.effect));
  }
  return names;
}

std::string Describe(const gap::Diagnosis& d) {
  std::string text = d.conclusion + ":";
  for (const gap::EffectResult& r : d.effects) {
    if (r.verdict != "rejected") text += " " + std::string(gap::EffectName(r.effect)) + " (" + r.verdict + ")";
  }
  return text + "; tau " + std::to_string(d.design.thermal_time_constant_s) + " s; held out " + std::to_string(d.holdout_before.rms_m * 1e6) + " -> " +
         std::to_string(d.holdout_after.rms_m * 1e6) + " um; " + d.unexplained_note;
}

TEST(BlindDiagnosis, EffectFreeIsNone) {
  const gap::Diagnosis d = DiagnoseBlind({});
  EXPECT_EQ(d.conclusion, "none") << d.unexplained_note;
  EXPECT_TRUE(Identified(d).empty());
}

TEST(BlindDiagnosis, ScrewsOfTheOtherHandArePassiveRotation) {
  BlindEffects e;
  e.pr_override = true;
  e.true_pr_sign = -1;
  const gap::Diagnosis d = DiagnoseBlind(e);
  EXPECT_EQ(Identified(d), std::vector<std::string>{"passive_rotation"});
  EXPECT_EQ(d.conclusion, "effects") << d.unexplained_note;
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m);
}

std::string VerdictOf(const gap::Diagnosis& d, gap::Effect effect) {
  for (const gap::EffectResult& r : d.effects) {
    if (r.effect == effect) return r.verdict;
  }
  return "absent";
}

// 36 parameters fitted on five runs predict the sixth less well than they
// fit: the held-out residual alone looks structured. The fit's own is white,
// so nothing unknown is claimed. Leg offsets, nested in joint centres (a
// joint moved along its leg), are not named beside them: the richer model is
// clearly better held out.
TEST(BlindDiagnosis, JointCentresAreIdentifiedAloneWithNothingUnknownLeft) {
  BlindEffects e;
  e.base_joint_error_m.row(0) << 300e-6, -200e-6, 100e-6, -250e-6, 150e-6, 300e-6;
  e.platform_joint_error_m.row(1) << -200e-6, 250e-6, -300e-6, 100e-6, 200e-6, -150e-6;
  const gap::Diagnosis d = DiagnoseBlind(e, 3e-6);
  EXPECT_EQ(Identified(d), std::vector<std::string>{"joint_position"}) << Describe(d);
  EXPECT_EQ(VerdictOf(d, gap::Effect::kLegOffset), "rejected") << Describe(d);
  EXPECT_EQ(d.conclusion, "effects") << Describe(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m) << Describe(d);
}

// Leg offsets alone: joint centres could fit them too (with 30 more
// parameters) and do no better held out, so the simpler is identified,
// not called ambiguous with the richer.
TEST(BlindDiagnosis, LegOffsetsAreIdentifiedAsTheSimplerOfTheNestedPair) {
  BlindEffects e;
  e.leg_offset_m << 120e-6, -250e-6, 60e-6, 180e-6, -90e-6, 300e-6;
  const gap::Diagnosis d = DiagnoseBlind(e);
  EXPECT_EQ(Identified(d), std::vector<std::string>{"leg_offset"}) << Describe(d);
  EXPECT_EQ(VerdictOf(d, gap::Effect::kJointPosition), "rejected") << Describe(d);
  EXPECT_EQ(d.conclusion, "effects") << Describe(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m) << Describe(d);
}

// Screws warming with time under power (the motors' heat), not with
// travel, and growing over a fixed length plus the stroke: thermal drift
// alone, its time constant estimated from the grid, the held-out gap closed.
TEST(BlindDiagnosis, ScrewsWarmingWithTimeAreThermalDriftWithTheirTimeConstant) {
  BlindEffects e;
  e.alpha_per_K = 11.7e-6;
  e.heating_K_per_s = 0.01;
  e.thermal_tau_s = 400.0;
  const gap::Diagnosis d = DiagnoseBlind(e, 5e-6);
  EXPECT_EQ(Identified(d), std::vector<std::string>{"thermal_drift"}) << Describe(d);
  EXPECT_GE(d.design.thermal_time_constant_s, 150.0) << Describe(d);
  EXPECT_LE(d.design.thermal_time_constant_s, 1200.0) << Describe(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m) << Describe(d);
}

// Warming by travel (friction in the nut): the same effect, with no lead
// error named beside it for the stroke-proportional part of the growth.
TEST(BlindDiagnosis, ScrewsWarmingWithTravelAreThermalDriftAlone) {
  BlindEffects e;
  e.alpha_per_K = 11.7e-6;
  e.heating_K_per_m = 6.0;
  e.thermal_tau_s = 800.0;
  const gap::Diagnosis d = DiagnoseBlind(e, 5e-6);
  EXPECT_EQ(Identified(d), std::vector<std::string>{"thermal_drift"}) << Describe(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m) << Describe(d);
}

// The tracker's stand vibrating at 6 Hz: nothing in the vocabulary, and its
// RMS at A only ~1.15× the tracker's noise floor (the RMS rule edsp had, 1.5×
// the floor, called this white). The evidence says structure.
TEST(BlindDiagnosis, AVibrationBarelyAboveTheNoiseIsUnknownAndItsFrequencyFound) {
  BlindEffects e;
  e.floor_hz = 6.0;
  e.floor_amplitude_m = 12e-6;
  e.floor_direction = Vec3(1.0, 0.5, 0.2);
  const gap::Diagnosis d = DiagnoseBlind(e);
  EXPECT_EQ(d.conclusion, "unknown") << Describe(d);
  EXPECT_TRUE(Identified(d).empty()) << Describe(d);
  EXPECT_LT(d.unexplained.rms_m, 1.5 * d.noise_floor_rms_m);
  EXPECT_NEAR(d.structure.dominant_hz, 6.0, 0.1) << d.unexplained_note;
}

TEST(BlindDiagnosis, AStructuralSwayIsUnknown) {
  BlindEffects e;
  e.resonance_hz = 1.5;
  e.resonance_damping = 0.03;
  e.resonance_gain = 0.5;
  const gap::Diagnosis d = DiagnoseBlind(e);
  EXPECT_TRUE(d.structure.structured) << Describe(d);
  EXPECT_NE(d.conclusion.find("unknown"), std::string::npos);
}

// A 3 Hz sway seen by a 20 Hz tracker: its quasi-static part follows A's
// acceleration, which servo lag's acceleration term fits (held out 94 →
// 29 µm), so selection takes servo lag. A mode beside the frame predicts
// the held-out runs as well, so servo lag is not identified (and no
// calibration applies it): the conclusion is `unknown`.
TEST(BlindDiagnosis, AnEffectTheStructureExplainsAsWellIsNotIdentified) {
  BlindEffects e;
  e.resonance_hz = 3.0;
  e.resonance_damping = 0.03;
  e.resonance_gain = 0.4;
  const gap::Diagnosis d = DiagnoseBlind(e, 10e-6, 20.0);
  EXPECT_EQ(d.conclusion, "unknown") << Describe(d);
  EXPECT_TRUE(Identified(d).empty()) << Describe(d);
  ASSERT_EQ(d.selected, std::vector<gap::Effect>{gap::Effect::kServoLag}) << Describe(d);
  for (const gap::EffectResult& r : d.effects) {
    if (r.effect != gap::Effect::kServoLag) continue;
    EXPECT_EQ(r.verdict, "ambiguous");
    EXPECT_EQ(r.ambiguous_with, std::vector<std::string>{"unknown"});
  }
}

// A 7.4 Hz sway seen by a tracker with encoder columns (the development
// seed's scenario 74, at 100 Hz instead of 321 to keep the test short): servo lag's acceleration term fits the
// sway's quasi-static part and leaves the rest white, so the structure
// check has nothing to go on. But the drives' own tracking error (command −
// encoder) shows almost none of that lag: it lies after the motor, and
// servo lag is not identified.
TEST(BlindDiagnosis, ALagTheEncodersDoNotShowIsNotTheDrives) {
  const BlindScenario s = DrawBlindScenario(7, 74);
  ASSERT_EQ(s.truth, std::vector<std::string>{"structural_resonance"}) << s.description;
  ASSERT_TRUE(s.tracker.encoders);
  TrackerOptions tracker = s.tracker;
  tracker.rate_hz = 100.0;
  const PlatformConfig config = Huang2021Config();
  const gap::Diagnosis d = gap::Diagnose(
      PlatformModel(config),
      gap::ParseMeasurementCsv(GenerateMeasurementCsv(SetupFromConfig(config), s.effects, tracker), "blind"));
  EXPECT_FALSE(d.structure.structured) << Describe(d);  // what makes this case the encoders' to decide
  EXPECT_TRUE(Identified(d).empty()) << Describe(d);
  EXPECT_EQ(d.conclusion, "unknown") << Describe(d);
  EXPECT_EQ(VerdictOf(d, gap::Effect::kServoLag), "ambiguous") << Describe(d);
}

// The same sway beside leg offsets: the offsets' gain is no mode's, and
// they stay identified.
TEST(BlindDiagnosis, AnEffectBesideAStructuralSwayStaysIdentified) {
  BlindEffects e;
  e.resonance_hz = 3.0;
  e.resonance_damping = 0.03;
  e.resonance_gain = 0.4;
  e.leg_offset_m << 120e-6, -80e-6, 150e-6, -60e-6, 90e-6, -140e-6;
  const gap::Diagnosis d = DiagnoseBlind(e, 10e-6, 20.0);
  const std::vector<std::string> identified = Identified(d);
  EXPECT_NE(std::find(identified.begin(), identified.end(), "leg_offset"), identified.end()) << Describe(d);
  EXPECT_NE(d.conclusion.find("unknown"), std::string::npos) << Describe(d);
}

// Compliance of the development seed's scenario 1 (tracker 30 Hz, 17 µm),
// measured on three runs only: a lead error explains the heave and the two
// mixed motions nearly as well, and a paired test over three held-out runs
// cannot tell the two apart. A true tie stays ambiguous, each named with the
// other. (With the design's acceleration over uneven steps, the base tilt
// this test used until 2026-11-26 no longer ties: compliance and joint
// centres are both identified there, the benchmark's out-of-vocabulary miss.)
TEST(BlindDiagnosis, TwoEffectsTheRunsCannotTellApartStayAmbiguous) {
  const BlindScenario s = DrawBlindScenario(7, 1);
  ASSERT_EQ(s.truth, std::vector<std::string>{"compliance"}) << s.description;
  const PlatformConfig config = Huang2021Config();
  BlindRigSetup setup = SetupFromConfig(config);
  setup.motions = {"Lz", "M1", "M2"};
  const gap::Diagnosis d =
      gap::Diagnose(PlatformModel(config), gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, s.effects, s.tracker), "blind"));
  EXPECT_TRUE(Identified(d).empty()) << Describe(d);
  const auto named_with = [&](gap::Effect effect, const std::string& other) {
    for (const gap::EffectResult& r : d.effects) {
      if (r.effect != effect) continue;
      return r.verdict == "ambiguous" &&
             std::find(r.ambiguous_with.begin(), r.ambiguous_with.end(), other) != r.ambiguous_with.end();
    }
    return false;
  };
  EXPECT_TRUE(named_with(gap::Effect::kCompliance, "lead_error")) << Describe(d);
  EXPECT_TRUE(named_with(gap::Effect::kLeadError, "compliance")) << Describe(d);
}

}  // namespace
}  // namespace edsp::blind
