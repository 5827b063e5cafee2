// edsp-gap drift on sessions of one rig after its calibration: nothing
// changed, a screw's backlash grown and a leg's offset jumped (recorded with
// the calibration applied, as a rig team records, and without it), and a
// payload added. The truth is the rig's (rig/), the fit edsp-gap's.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/drift.h"
#include "edsp/gap/drift_benchmark.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "command_output.h"
#include "offline_session.h"
#include "scratch_dir.h"
#include "platform_models.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {
namespace {

RigEffects Rig() { return test_support::OffsetsBacklashAndLead(); }

// A session: its motions on the rig, with the calibration `model` applied
// by the kinematics (empty: none), the tracker set up anew.
std::string Session(const std::string& name, const RigEffects& fx, const std::vector<std::string>& motions,
                    const std::string& model, std::uint64_t seed) {
  const Pose tracker = Pose::FromVector(
      (Vector6() << 1.0 + static_cast<double>(seed), -2.0, 0.2, 0.01, -0.01, 0.3 * static_cast<double>(seed))
          .finished());
  OfflineRunOptions o =
      test_support::OfflineSession(motions, 4, 0.3, 5e-6, seed, tracker, test_support::ScratchDir("drift_" + name));
  o.calibration_path = model;
  return RunOffline(test_support::kShippedConfig, fx, o).csv_path;
}

// The calibration in force: diagnosed on six motions, saved as a user saves it.
const std::string& Baseline() {
  static const std::string path = [] {
    const std::string csv = Session("fit", Rig(), {"Lz", "Lx", "Rz", "Ry", "M1", "M2"}, "", 1);
    const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(csv));
    const std::string out = test_support::ScratchDir("drift_baseline") + "/model.json";
    std::ofstream(out) << ModelJson(d).dump(2);
    return out;
  }();
  return path;
}

nlohmann::json BaselineJson() { return nlohmann::json::parse(std::ifstream(Baseline())); }

const std::vector<std::string> kSession = {"Lz", "Lx", "Ry", "M3"};
const std::vector<std::string> kFit = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};

const ParameterChange* Find(const std::vector<ParameterChange>& changes, Effect e, int leg) {
  for (const ParameterChange& c : changes) {
    if (c.effect == e && c.leg == leg) return &c;
  }
  return nullptr;
}

// The team's own bar: recalibrate when the calibration leaves more than
// 11 µm RMS (the tracker's floor is 8.7 µm).
DriftOptions Team() {
  DriftOptions o;
  o.threshold_m = 11e-6;
  return o;
}

TEST(Drift, ARigThatDidNotChangeNeedsNoRecalibration) {
  const DriftReport r = Drift(test_support::ShippedConfigModel(), BaselineJson(), Baseline(),
                              LoadMeasurement(Session("same", Rig(), kSession, Baseline(), 2)), Team());
  EXPECT_TRUE(r.changed.empty()) << DriftText(r);
  EXPECT_TRUE(r.appeared.empty()) << DriftText(r);
  EXPECT_TRUE(r.vanished.empty()) << DriftText(r);
  EXPECT_FALSE(r.recalibrate) << DriftText(r);
  EXPECT_FALSE(r.parameters.empty());
}

// Backlash of screw 3 grown by 20 µm, leg 2's offset jumped by 80 µm: both
// named and sized within 3σ of the truth, nothing else, whether the
// session ran with the calibration or without it.
TEST(Drift, WornBacklashAndAJumpedOffsetAreNamedAndSized) {
  RigEffects worn = Rig();
  worn.backlash.backlash_m[2] += 20e-6;
  worn.leg_offset.offset_m[1] += 80e-6;
  for (const bool with : {true, false}) {
    DriftOptions o = Team();
    o.recorded_with_baseline = with;
    const std::string csv = Session(with ? "worn_with" : "worn_without", worn, kSession, with ? Baseline() : "", 3);
    const DriftReport r =
        Drift(test_support::ShippedConfigModel(), BaselineJson(), Baseline(), LoadMeasurement(csv), o);
    SCOPED_TRACE(DriftText(r));
    const ParameterChange* backlash = Find(r.changed, Effect::kBacklash, 3);
    const ParameterChange* offset = Find(r.changed, Effect::kLegOffset, 2);
    ASSERT_NE(backlash, nullptr);
    ASSERT_NE(offset, nullptr);
    EXPECT_NEAR(backlash->change, 20e-6, 3.0 * backlash->sigma + 1e-6);
    EXPECT_NEAR(offset->change, 80e-6, 3.0 * offset->sigma + 2e-6);
    EXPECT_NEAR(backlash->after, backlash->before + backlash->change, 1e-15);
    EXPECT_EQ(r.changed.size(), 2u);
    EXPECT_TRUE(r.recalibrate);
    EXPECT_EQ(r.recorded_with_baseline, with);
  }
}

// The rig with its joint centres off too: a calibration of it holds the
// legs' lengths in joint centres, beside which an offset cannot be told
// apart on a session's motions.
RigEffects WithJointCentres() {
  RigEffects fx = Rig();
  fx.joint_position.enabled = true;
  for (int leg = 0; leg < 6; ++leg) {
    for (int axis = 0; axis < 3; ++axis) {
      fx.joint_position.base_m(axis, leg) = 150e-6 * std::sin(1.0 + 2.1 * leg + 0.7 * axis);
      fx.joint_position.platform_m(axis, leg) = 120e-6 * std::cos(0.4 + 1.3 * leg + 1.9 * axis);
    }
  }
  return fx;
}

// A screw worn to 2.5× its play and another leg re-seated 40 µm longer, in
// one session, on a rig whose calibration holds joint centres: the leg is
// named by its length, on its own leg, and sized; the backlash too; no
// other leg and no parameter of another leg changed.
TEST(Drift, AGrownBacklashBesideAJumpedLegAreEachNamedOnTheirOwnLeg) {
  const std::string fit = Session("joints_fit", WithJointCentres(), kFit, "", 6);
  const Diagnosis d = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(fit));
  const std::string model = test_support::ScratchDir("drift_joints") + "/model.json";
  std::ofstream(model) << ModelJson(d).dump(2);
  const nlohmann::json baseline = nlohmann::json::parse(std::ifstream(model));
  RigEffects changed = WithJointCentres();
  changed.backlash.backlash_m[1] *= 2.5;
  changed.leg_offset.offset_m[3] += 40e-6;
  const DriftReport r = Drift(test_support::ShippedConfigModel(), baseline, model,
                              LoadMeasurement(Session("joints_changed", changed, kFit, model, 7)), Team());
  std::string applied;
  for (const auto& e : baseline["effects"])
    applied += " " + e.value("name", "") + (e.value("apply", false) ? "" : "(not applied)");
  std::string legs;
  for (const LegChange& c : r.legs) legs += LegChangeText(c) + fmt::format(" at A {:.1f} µm\n", c.at_a_m * 1e6);
  SCOPED_TRACE(DriftText(r) + legs + "baseline:" + applied);
  ASSERT_EQ(r.legs.size(), 6u);
  ASSERT_EQ(r.legs_changed.size(), 1u);
  EXPECT_EQ(r.legs_changed[0].leg, 4);
  EXPECT_NEAR(r.legs_changed[0].change_m, 40e-6, 3.0 * r.legs_changed[0].sigma_m);
  const ParameterChange* backlash = Find(r.changed, Effect::kBacklash, 2);
  ASSERT_NE(backlash, nullptr);
  EXPECT_NEAR(backlash->change, 1.5 * Rig().backlash.backlash_m[1], 3.0 * backlash->sigma + 1e-6);
  for (const ParameterChange& c : r.changed) {
    EXPECT_TRUE(c.leg == 2 || c.leg == 4) << ChangeText(c);
  }
  EXPECT_TRUE(r.recalibrate);
}

// A payload the calibration never saw: the legs give under it, an effect
// the baseline does not hold.
TEST(Drift, AnEffectTheBaselineDoesNotHoldAppears) {
  RigEffects loaded = Rig();
  loaded.compliance.enabled = true;
  loaded.compliance.stiffness_N_m.fill(1.5e7);
  loaded.compliance.mass_kg = 1200.0;
  const DriftReport r = Drift(test_support::ShippedConfigModel(), BaselineJson(), Baseline(),
                              LoadMeasurement(Session("loaded", loaded, kSession, Baseline(), 4)), Team());
  EXPECT_NE(std::find(r.appeared.begin(), r.appeared.end(), Effect::kCompliance), r.appeared.end()) << DriftText(r);
  EXPECT_TRUE(r.recalibrate) << DriftText(r);
}

// A periodic error's θ reads in pairs (no σ of its own for an amplitude
// or a phase): a change of one term says which, of which leg, in the
// amplitude's unit.
TEST(Drift, AChangeOfAPeriodicErrorsTermNamesItsLegTermAndUnit) {
  ParameterChange c;
  c.effect = Effect::kPeriodicLeadError;
  c.parameter = "theta";
  c.index = c.theta_index = 5;  // leg 3's cosine term: the text finds its leg
  c.before = 7e-6, c.after = 5e-6, c.change = -2e-6, c.sigma = 0.5e-6, c.z = -4.0;
  EXPECT_EQ(ChangeText(c), "periodic_lead_error amplitude, its cosine term leg 3: 7.0 → 5.0 µm, -2.0 ± 0.5 µm (4.0σ)");
  c.index = c.theta_index = 4;
  EXPECT_NE(ChangeText(c).find("its sine term leg 3"), std::string::npos) << ChangeText(c);
}

// The bound many parameters need, against the normal tail it stands for.
TEST(Drift, TheChangeThresholdKeepsNoiseFromCountingAsChange) {
  EXPECT_DOUBLE_EQ(ChangeThreshold(1), 3.0);
  for (int n : {100, 1000}) {
    const double z = ChangeThreshold(n);
    EXPECT_NEAR(n * std::erfc(z / std::sqrt(2.0)), 0.05, 1e-6) << n;
    EXPECT_NEAR(n * std::erfc(ChangeThreshold(n, 0.025) / std::sqrt(2.0)), 0.025, 1e-6) << n;
  }
}

TEST(Drift, TheCommandLineSaysWhatChangedAndRefusesABadBaseline) {
  const std::string csv = Session("cli", Rig(), kSession, Baseline(), 5);
  const auto ok =
      test_support::RunCommand(fmt::format("{} drift --config {} --baseline {} --data {} --json",
                                           BuiltProgram("edsp-gap"), test_support::kShippedConfig, Baseline(), csv));
  ASSERT_EQ(ok.exit_code, 0) << ok.text;
  const nlohmann::json j = nlohmann::json::parse(ok.text.substr(ok.text.find('{')));
  for (const char* key : {"changed", "legs", "legs_changed", "appeared", "vanished", "heldout_rms_m", "recalibrate"})
    EXPECT_TRUE(j.contains(key)) << key;
  // The legs' six lengths are judged as their own family, whatever the
  // number of the baseline's parameters: half the 5% chance over six.
  EXPECT_DOUBLE_EQ(j["leg_z_threshold"].get<double>(), 3.0);
  int applied = 0;
  for (const nlohmann::json& p : j["parameters"]) applied += p["applied"].get<bool>() ? 1 : 0;
  EXPECT_DOUBLE_EQ(j["z_threshold"].get<double>(), ChangeThreshold(applied, 0.025));
  // By default the data says whether the baseline was applied (its leg_corr columns).
  EXPECT_TRUE(j["recorded_with_baseline"].get<bool>());
  const auto without = test_support::RunCommand(
      fmt::format("{} drift --config {} --baseline {} --data {} --json", BuiltProgram("edsp-gap"),
                  test_support::kShippedConfig, Baseline(), Session("cli_without", Rig(), kSession, "", 5)));
  ASSERT_EQ(without.exit_code, 0) << without.text;
  const nlohmann::json w = nlohmann::json::parse(without.text.substr(without.text.find('{')));
  EXPECT_FALSE(w["recorded_with_baseline"].get<bool>());
  EXPECT_TRUE(w["changed"].empty()) << without.text;
  const std::string bad = test_support::ScratchDir("drift_bad") + "/bad.json";
  std::ofstream(bad) << R"({"format": "edsp-gap-model/1", "effects": [{"name": "backlash", "theta": [1, 2]}]})";
  const auto refused =
      test_support::RunCommand(fmt::format("{} drift --config {} --baseline {} --data {}", BuiltProgram("edsp-gap"),
                                           test_support::kShippedConfig, bad, csv));
  EXPECT_EQ(refused.exit_code, 1) << refused.text;
  EXPECT_NE(refused.text.find(bad), std::string::npos) << refused.text;
  EXPECT_NE(refused.text.find("needs 6 parameters"), std::string::npos) << refused.text;
  // The benchmark's sessions run the motions asked for.
  const auto bench = test_support::RunCommand(fmt::format(
      "{} benchmark --mode drift --scenarios 1 --seed 3 --session-motions Lz,Rz --json", BuiltProgram("edsp-gap")));
  ASSERT_EQ(bench.exit_code, 0) << bench.text;
  const nlohmann::json b = nlohmann::json::parse(bench.text.substr(bench.text.find('{')));
  EXPECT_EQ(b["session_motions"], (std::vector<std::string>{"Lz", "Rz"})) << bench.text;
  EXPECT_TRUE(b["scenarios"][0]["truth"][0].contains("reported")) << bench.text;
  // Drift is scored on edsp's rig only.
  const auto blind = test_support::RunCommand(
      fmt::format("{} benchmark --mode drift --generator blind --scenarios 1", BuiltProgram("edsp-gap")));
  EXPECT_EQ(blind.exit_code, 1) << blind.text;
  EXPECT_NE(blind.text.find("--mode drift --generator blind"), std::string::npos) << blind.text;
}

// Four random whole rigs (every static effect at once, a heavy payload),
// calibrated on the six motions and measured again with the calibration in
// force: the session where nothing changed names nothing, and the grown
// backlash of the first is named and sized. A whole rig's parameters move
// with the motion where the model is not the rig's: with σ the formal one
// alone, the third rig's compliance and the fourth's periodic error were
// named changes; with the periodic error evaluated at the nominal command's
// stroke, the first rig's.
TEST(Drift, AnUnchangedWholeRigIsQuietAndAGrownBacklashIsNamed) {
  DriftBenchmarkOptions o;
  o.rigs = 4;
  o.seed = 4242;
  o.progress = false;
  const DriftBenchmarkResult r = RunDriftBenchmark(o);
  ASSERT_EQ(r.scenarios.size(), 4u);
  for (const DriftScenario& s : r.scenarios) {
    ASSERT_TRUE(s.error.empty()) << s.error;
    EXPECT_TRUE(s.unchanged_quiet) << s.description << ": " << fmt::format("{}", fmt::join(s.unchanged_changes, "; "));
  }
  ASSERT_EQ(r.scenarios[0].kind, "backlash");
  ASSERT_FALSE(r.scenarios[0].truth.empty());
  const TrueChange& grown = r.scenarios[0].truth[0];
  EXPECT_TRUE(grown.eligible && grown.named && grown.sized)
      << grown.change << " reported " << grown.reported << " ± " << grown.sigma;
}

}  // namespace
}  // namespace edsp::gap
