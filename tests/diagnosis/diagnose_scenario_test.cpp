// The diagnosis on virtual-rig data whose truth the test knows and the
// diagnosis does not: each effect alone, a pair, none, an effect outside the
// vocabulary, the paper's unsigned compensation, and a saved model applied
// to data it never saw. (These scenarios are hand-set; the README's scores
// come from `edsp-gap benchmark` on random draws of another seed.)
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/report.h"
#include "edsp/gap/rig_scenarios.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "scratch_dir.h"
#include "platform_models.h"

namespace edsp::gap {
namespace {

constexpr double kNoise = 5e-6;

// A well-tuned drive (integral action) and strong enough motors: no effect.
RigEffects Baseline() {
  RigEffects fx;
  fx.servo_lag.integral_time_s = 0.05;
  fx.servo_lag.torque_limit_N_m = 15.0;
  return fx;
}

struct Simulated {
  std::string csv;
};

Simulated Simulate(const std::string& name, const RigEffects& fx, PrMode compensation = PrMode::kSigned,
                   std::uint64_t seed = 1,
                   const Vector6& frame = (Vector6() << 1.5, -2.0, 0.2, 0.01, -0.01, 2.0).finished()) {
  OfflineRunOptions o;
  o.motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
  o.paper.stops = 4;
  o.paper.dwell_s = 0.3;
  o.paper.max_speed_m_s = 0.25;
  o.paper.max_speed_rad_s = 0.5;
  o.pr_mode = compensation;
  o.tracker.noise_sigma_m = kNoise;
  o.tracker.rate_hz = 100.0;
  o.tracker.seed = seed;
  o.tracker.X_TB = Pose::FromVector(frame);
  o.out_dir = test_support::ScratchDir("gap_" + name);
  return {RunOffline(test_support::kShippedConfig, fx, o).csv_path};
}

std::vector<std::string> Found(const Diagnosis& d) {
  std::vector<std::string> names;
  for (const EffectResult& r : d.effects) {
    if (r.verdict != Verdict::kRejected) names.push_back(EffectName(r.effect));
  }
  return names;
}

const EffectResult& ResultFor(const Diagnosis& d, Effect e) {
  for (const EffectResult& r : d.effects) {
    if (r.effect == e) return r;
  }
  throw std::logic_error("effect missing from the ranking");
}

// On held-out runs: down to within 1.5× the noise floor, and at least 80%
// of the gap beyond the noise gone (a gap near the noise cannot shrink 80%).
void ExpectClosed(const Diagnosis& d) {
  EXPECT_DOUBLE_EQ(d.gap_shrink, GapShrink(d.holdout_before.rms_m, d.holdout_after.rms_m, d.noise_floor_rms_m));
  EXPECT_GE(d.gap_shrink, 0.8) << "held-out gap " << d.holdout_before.rms_m << " → " << d.holdout_after.rms_m
                               << " m, noise floor " << d.noise_floor_rms_m << " m";
  EXPECT_LE(d.holdout_after.rms_m, 1.5 * d.noise_floor_rms_m);
}

TEST(Diagnose, EffectFreeDataIdentifiesNothing) {
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Simulate("clean", Baseline()).csv));
  EXPECT_EQ(d.conclusion, Conclusion::kNone);
  EXPECT_TRUE(d.selected.empty());
  for (const EffectResult& r : d.effects) EXPECT_EQ(r.verdict, Verdict::kRejected) << EffectName(r.effect);
  // The noise floor is the tracker's: √3 · σ.
  EXPECT_NEAR(d.noise_floor_rms_m, std::sqrt(3.0) * kNoise, 0.15 * std::sqrt(3.0) * kNoise);
  EXPECT_LE(d.holdout_after.rms_m, 1.1 * d.noise_floor_rms_m);
  EXPECT_LT(std::abs(d.whiteness.lag1), 0.1) << "what is left is (nearly) white";
  // A stiff loop: the drives' following error is under the tracker's noise.
  const nlohmann::json drives = ToJson(d)["drives"];
  EXPECT_FALSE(drives["rest_taken_out"].get<bool>()) << drives.dump();
  EXPECT_LT(drives["rest_rms_m"].get<double>(), d.noise_floor_rms_m / std::sqrt(3.0)) << drives.dump();
}

struct SingleCase {
  Effect effect;
  void (*set)(RigEffects*);
};

class SingleEffect : public testing::TestWithParam<SingleCase> {};

TEST_P(SingleEffect, IsRankedFirstAndClosesTheHeldOutGap) {
  RigEffects fx = Baseline();
  GetParam().set(&fx);
  const Diagnosis d =
      Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Simulate(EffectName(GetParam().effect), fx).csv));
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(EffectName(d.effects.front().effect), std::string(EffectName(GetParam().effect)))
      << "found: " << fmt::format("{}", fmt::join(Found(d), ", "));
  EXPECT_NE(d.effects.front().verdict, Verdict::kRejected);
  EXPECT_EQ(d.conclusion, Conclusion::kEffects) << d.unexplained_note;
  ExpectClosed(d);
}

const SingleCase kSingles[] = {
    {Effect::kPassiveRotation,
     [](RigEffects* f) { f->passive_rotation.enabled = true, f->passive_rotation.pr_sign = -1; }},
    {Effect::kLegOffset,
     [](RigEffects* f) {
       f->leg_offset.enabled = true, f->leg_offset.offset_m = {80e-6, -60e-6, 40e-6, -100e-6, 50e-6, -20e-6};
     }},
    {Effect::kJointPosition,
     [](RigEffects* f) {
       f->joint_position.enabled = true;
       f->joint_position.base_m << 1e-4, -8e-5, 0, 6e-5, -1.5e-4, 0, -5e-5, 0, 1.2e-4, -1e-4, 2e-5, 0, 0, 5e-5, -4e-5,
           0, 3e-5, -1e-4;
       f->joint_position.platform_m << 5e-5, 0, -4e-5, 0, 3e-5, -6e-5, 0, -7e-5, 4e-5, 0, -3e-5, 0, 0, 2e-5, 0, 6e-5, 0,
           -2e-5;
     }},
    {Effect::kLeadError,
     [](RigEffects* f) {
       f->lead_error.enabled = true, f->lead_error.epsilon = {1.5e-4, -1e-4, 2e-4, 0.5e-4, -1.5e-4, 1e-4};
     }},
    {Effect::kPeriodicLeadError,
     [](RigEffects* f) {
       f->periodic_lead_error.enabled = true;
       f->periodic_lead_error.amplitude_m = {12e-6, 10e-6, 12e-6, 10e-6, 12e-6, 10e-6};
       f->periodic_lead_error.phase_rad = {0.0, 1.1, 2.3, 3.0, 4.2, 5.5};
     }},
    {Effect::kBacklash,
     [](RigEffects* f) {
       f->backlash.enabled = true, f->backlash.backlash_m = {20e-6, 30e-6, 40e-6, 50e-6, 25e-6, 35e-6};
     }},
    {Effect::kServoLag, [](RigEffects* f) { f->servo_lag.bandwidth_hz = 12.0, f->servo_lag.integral_time_s = 0.0; }},
    {Effect::kCompliance,
     [](RigEffects* f) {
       f->compliance.enabled = true;
       f->compliance.stiffness_N_m = {2e7, 2.2e7, 1.9e7, 2.1e7, 1.8e7, 2e7};
       f->compliance.mass_kg = 800.0;
       f->compliance.com_m = Vector3(0.0, 0.0, 0.1);
     }},
    {Effect::kThermalDrift,
     [](RigEffects* f) {
       f->thermal_drift.enabled = true, f->thermal_drift.heating_K_per_m = 5.0,
       f->thermal_drift.time_constant_s = 900.0;
     }},
};

INSTANTIATE_TEST_SUITE_P(EveryEffect, SingleEffect, testing::ValuesIn(kSingles),
                         [](const testing::TestParamInfo<SingleCase>& p) {
                           return std::string(EffectName(p.param.effect));
                         });

// Lead errors alone (the first such scenario of the benchmark's seed 101):
// compliance, whose leg forces also grow with the stroke, fits part of the
// same gap, but in lead error's place it takes up only half its held-out
// gain (50%, under the tie's 70%), so the two are no tie. (Where the ratio
// is reached and the runs decide: the blind rig's
// ATiltTheRunsTellFromCompliantLegsIsNoTie and its sway tests.)
TEST(Diagnose, AnAlternativeThatTakesUpHalfTheGainIsNoTie) {
  Scenario drawn;
  for (int index = 1; index < 200 && drawn.truth != std::vector<Effect>{Effect::kLeadError}; ++index) {
    drawn = DrawScenario(101, index);
  }
  ASSERT_EQ(drawn.truth, std::vector<Effect>{Effect::kLeadError}) << drawn.description;
  RigEffects fx = drawn.effects;
  const Diagnosis d =
      Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Simulate("lead_vs_compliance", fx).csv));
  EXPECT_EQ(ResultFor(d, Effect::kLeadError).verdict, Verdict::kIdentified)
      << fmt::format("{}", fmt::join(Found(d), ", "));
  EXPECT_EQ(ResultFor(d, Effect::kCompliance).verdict, Verdict::kRejected)
      << fmt::format("{}", fmt::join(Found(d), ", "));
}

// Without encoder columns a tracker clock offset is a lag equal on every
// leg and a pure delay (docs/diagnosis.md, step 12). The rig's soft drive
// runs velocity feed-forward, so its motor lags the command with the
// acceleration, under each leg's own load: no delay fits that (δ comes out
// 0.02 ± 0.03 ms), and the lag must stay the drives'. This guards against
// leaving every lag seen without encoders to the clock; the blind rig's
// tests (tracker_clock_test.cpp) guard the offset's own rule.
TEST(Diagnose, WithoutEncodersADrivesLoopIsNotTakenForAClockOffset) {
  RigEffects fx = Baseline();
  fx.servo_lag.bandwidth_hz = 12.0, fx.servo_lag.integral_time_s = 0.0;
  MeasurementData data = LoadMeasurement(Simulate("lag_without_encoders", fx).csv);
  for (MeasurementRow& row : data.rows) row.has_encoder = false;
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), data);
  ASSERT_TRUE(d.clock_offset.tested);
  EXPECT_FALSE(d.clock_offset.replaces_lag) << d.unexplained_note;
  EXPECT_EQ(ResultFor(d, Effect::kServoLag).verdict, Verdict::kIdentified)
      << ResultFor(d, Effect::kServoLag).next_measurement;
  EXPECT_EQ(d.conclusion, Conclusion::kEffects) << d.unexplained_note;
  EXPECT_FALSE(ToJson(d).contains("drives")) << "no encoders, no following error to report";
}

// A soft drive loop with integral action (10 Hz) under a heavy payload on
// compliant legs: after each change of acceleration the loop rings and the
// payload's load changes faster than the integral follows. servo_lag's
// terms (velocity, acceleration, jerk) describe only part of that; the
// encoders record all of it, and the design takes out the rest as measured
// (design.h). Left in, it stayed as structure no effect explains
// (`unknown`, here 3× the noise floor held out) or was named a swaying
// structure this rig does not have.
TEST(Diagnose, ARingingDriveLoopIsTheDrivesNotASwayingStructure) {
  RigEffects fx = Baseline();
  fx.servo_lag.bandwidth_hz = 10.0;
  fx.servo_lag.integral_time_s = 5.0 / (2.0 * M_PI * fx.servo_lag.bandwidth_hz);
  fx.compliance.enabled = true;
  fx.compliance.stiffness_N_m = {16e6, 15e6, 17e6, 15.5e6, 16.5e6, 15e6};
  fx.compliance.mass_kg = 900.0;
  fx.compliance.com_m = Vector3(0.0, 0.0, 0.15);
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Simulate("ringing_drive", fx).csv));
  EXPECT_EQ(ResultFor(d, Effect::kServoLag).verdict, Verdict::kIdentified);
  EXPECT_EQ(ResultFor(d, Effect::kCompliance).verdict, Verdict::kIdentified);
  EXPECT_EQ(ResultFor(d, Effect::kStructuralResonance).verdict, Verdict::kRejected);
  EXPECT_EQ(d.conclusion, Conclusion::kEffects) << d.unexplained_note;
  ExpectClosed(d);
  // The report says so: the rest of the following error, above the
  // tracker's noise, was taken out before any effect was fitted.
  const nlohmann::json drives = ToJson(d)["drives"];
  EXPECT_TRUE(drives["rest_taken_out"].get<bool>()) << drives.dump();
  EXPECT_GT(drives["rest_rms_m"].get<double>(), d.noise_floor_rms_m / std::sqrt(3.0)) << drives.dump();
  EXPECT_GT(drives["described_rms_m"].get<double>(), 0.0) << drives.dump();
}

TEST(Diagnose, BacklashAndLeadErrorAreRecoveredWithTheirSizes) {
  RigEffects fx = Baseline();
  fx.backlash.enabled = true;
  fx.backlash.backlash_m = {20e-6, 30e-6, 40e-6, 50e-6, 25e-6, 35e-6};
  fx.lead_error.enabled = true;
  fx.lead_error.epsilon = {1.5e-4, -1e-4, 2e-4, 0.5e-4, -1.5e-4, 1e-4};
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Simulate("pair", fx).csv));
  ASSERT_EQ(d.selected.size(), 2u) << fmt::format("{}", fmt::join(Found(d), ", "));
  const EffectResult& backlash = ResultFor(d, Effect::kBacklash);
  const EffectResult& lead = ResultFor(d, Effect::kLeadError);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(backlash.theta(i), fx.backlash.backlash_m[static_cast<std::size_t>(i)], 3e-6) << "leg " << i + 1;
    EXPECT_NEAR(lead.theta(i), fx.lead_error.epsilon[static_cast<std::size_t>(i)], 1.5e-5) << "leg " << i + 1;
    EXPECT_LT(backlash.sigma(i), 2e-6);  // uncertainties that mean something
  }
  ExpectClosed(d);
}

// A 1.3 Hz vibration of point A on the clock (not driven by the motion, so
// not the structural mode of the vocabulary), added to clean measurements:
// structured, and no effect of the vocabulary.
TEST(Diagnose, AnEffectOutsideTheVocabularyIsUnknown) {
  const std::string csv = Simulate("sway", Baseline()).csv;
  std::ifstream in(csv);
  std::ostringstream swayed;
  std::string line;
  std::getline(in, line);
  swayed << line << "\n";
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) f.push_back(cell);
    const double t = std::stod(f[0]);
    f[f.size() - 3] = fmt::format("{:.12f}", std::stod(f[f.size() - 3]) + 40e-6 * std::sin(2 * M_PI * 1.3 * t));
    swayed << fmt::format("{}", fmt::join(f, ",")) << "\n";
  }
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), ParseMeasurementCsv(swayed.str(), "swayed.csv"));
  EXPECT_EQ(d.conclusion, Conclusion::kUnknown) << d.unexplained_note;
  EXPECT_FALSE(d.whiteness.white);
  const nlohmann::json j = ToJson(d);
  bool unknown_listed = false;
  for (const auto& e : j["effects"]) unknown_listed |= e["name"] == "unknown";
  EXPECT_TRUE(unknown_listed);
}

// The paper's case: the rig's screws follow the signed twist, the controller
// compensates with Eq. (9)'s unsigned angle. The diagnosis names PR, and the
// signed model closes the gap.
TEST(Diagnose, ThePapersUnsignedCompensationIsPassiveRotationAndSignedClosesIt) {
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(),
                               LoadMeasurement(Simulate("paper", Baseline(), PrMode::kUnsigned).csv));
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().effect, Effect::kPassiveRotation);
  EXPECT_EQ(d.effects.front().verdict, Verdict::kIdentified);
  EXPECT_EQ(d.applied_pr, PrMode::kUnsigned);
  const nlohmann::json j = ToJson(d);
  EXPECT_EQ(j["compensation"]["pr_mode"], "signed");
  EXPECT_NEAR(j["compensation"]["pr_scale"].get<double>(), 1.0, 0.02);
  EXPECT_GT(d.holdout_before.rms_m, 100e-6);  // hundreds of µm, as in the paper's Table 1
  EXPECT_GE(d.shrink, 0.9);
  ExpectClosed(d);
}

// A model saved from one campaign, applied to another of the same rig with
// the tracker moved and fresh noise: the effects carry over, the frame not.
TEST(Evaluate, ASavedModelShrinksTheGapOnDataItNeverSaw) {
  RigEffects fx = Baseline();
  fx.lead_error.enabled = true;
  fx.lead_error.epsilon = {1.5e-4, -1e-4, 2e-4, 0.5e-4, -1.5e-4, 1e-4};
  fx.compliance.enabled = true;
  fx.compliance.stiffness_N_m = {2e7, 2e7, 2e7, 2e7, 2e7, 2e7};
  fx.compliance.mass_kg = 600.0;
  const PlatformModel model = test_support::ShippedConfigModel();
  const Diagnosis d = Diagnose(model, LoadMeasurement(Simulate("train", fx).csv));
  const nlohmann::json saved = ModelJson(d);
  const Evaluation ev = Evaluate(
      model,
      LoadMeasurement(
          Simulate("test", fx, PrMode::kSigned, 99, (Vector6() << -2.5, 1.0, -0.3, 0, 0.02, -1.0).finished()).csv),
      saved, "model.json");
  EXPECT_GE(ev.shrink, 0.8) << ev.before.rms_m << " → " << ev.after.rms_m;
  EXPECT_LT(ev.after.rms_m, 1.5 * std::sqrt(3.0) * kNoise);
  // A model with a wrong parameter count is refused with its name.
  nlohmann::json broken = saved;
  broken["effects"][0]["theta"] = {1.0};
  EXPECT_THROW(Evaluate(model, LoadMeasurement(Simulate("train", fx).csv), broken, "model.json"), MeasurementError);
  // A structural mode without its frequency, or with a frequency that is not a number, is refused by name.
  const MeasurementData data = LoadMeasurement(Simulate("train", fx).csv);
  nlohmann::json mode = saved;
  mode["effects"] = {{{"name", "structural_resonance"}, {"theta", {0.2, 0.2, 0.1}}}};
  const auto refusal = [&](const nlohmann::json& m) {
    try {
      Evaluate(model, data, m, "model.json");
    } catch (const MeasurementError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(mode).find("needs \"structural_mode_hz\" > 0"), std::string::npos) << refusal(mode);
  mode["structural_mode_hz"] = "five";
  EXPECT_NE(refusal(mode).find("\"structural_mode_hz\" must be a number"), std::string::npos) << refusal(mode);
  mode["structural_mode_hz"] = 5.0;
  EXPECT_EQ(refusal(mode), "accepted");
}

}  // namespace
}  // namespace edsp::gap
