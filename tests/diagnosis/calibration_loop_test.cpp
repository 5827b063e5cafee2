// The loop closed, offline on the stack's own classes (planner → kinematics
// → bridge → virtual rig): a rig with effects is measured on calibration
// motions, edsp-gap identifies the effects, and the kinematics applies the
// saved model on motions the fit never saw. The rig's physics are written
// apart from the error model the diagnosis fits and the calibration applies
// (rig/ against kinematics/leg_error_model), so a shared bug cannot hide.
// Errors are after the best rigid alignment (the tracker's frame is as
// unknown to a rig team as to the diagnosis).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {
namespace {

constexpr double kNoiseSigma = 5e-6;
const double kNoiseFloor = std::sqrt(3.0) * kNoiseSigma;  // RMS of the tracker's noise at A

std::string Config() { return SourcePath("config/huang2021-rig-effects.toml"); }

OfflineRunOptions Run(const std::string& dir, std::vector<std::string> motions, std::uint64_t seed) {
  OfflineRunOptions o;
  o.motions = std::move(motions);
  o.paper.stops = 5;
  o.paper.dwell_s = 0.5;
  o.paper.max_speed_m_s = 0.25;
  o.paper.max_speed_rad_s = 0.5;
  o.tracker.noise_sigma_m = kNoiseSigma;
  o.tracker.seed = seed;
  o.out_dir = dir;
  return o;
}

// RMS of point A's error after the best rigid alignment of the run.
double AlignedRms(const std::string& csv) {
  return Evaluate(PlatformModel(LoadConfigFile(Config())), LoadMeasurement(csv), EmptyModelJson(), "none").before.rms_m;
}

struct LoopResult {
  double before_m = 0.0, after_m = 0.0;
  std::string calibration;
};

// Calibration motions → diagnosis → model → held-out motions without and with it.
LoopResult CloseTheLoop(const RigEffects& effects, const std::string& name, bool apply_ambiguous = false) {
  const std::string dir = test_support::ScratchDir("calibration_loop_" + name);
  std::filesystem::remove_all(dir);
  const OfflineRunResult fit =
      RunOffline(Config(), effects, Run(dir + "/fit", {"Lz", "Lx", "Rz", "Ry", "M1", "M2"}, 1));
  const Diagnosis d = Diagnose(PlatformModel(LoadConfigFile(Config())), LoadMeasurement(fit.csv_path));
  const std::string model = dir + "/model.json";
  std::ofstream(model) << ModelJson(d).dump(2);
  const std::vector<std::string> held_out = {"Ly", "Rx", "M3"};
  LoopResult r;
  r.before_m = AlignedRms(RunOffline(Config(), effects, Run(dir + "/before", held_out, 2)).csv_path);
  OfflineRunOptions with = Run(dir + "/after", held_out, 2);
  with.calibration_path = model;
  with.apply_ambiguous = apply_ambiguous;
  const OfflineRunResult after = RunOffline(Config(), effects, with);
  r.after_m = AlignedRms(after.csv_path);
  r.calibration = after.calibration;
  std::filesystem::remove_all(dir);
  return r;
}

std::string Describe(const LoopResult& r) {
  return fmt::format("held out {:.1f} -> {:.1f} um RMS (noise floor {:.1f} um); {}", r.before_m * 1e6, r.after_m * 1e6,
                     kNoiseFloor * 1e6, r.calibration);
}

// Every effect of the example rig at once: the held-out error falls to
// within 1.5× the tracker's noise floor.
TEST(CalibrationLoop, EveryEffectAtOnceLandsAtTheNoiseFloorOnMotionsTheFitNeverSaw) {
  const LoopResult r = CloseTheLoop(LoadRigEffects(Config()), "all");
  std::printf("CALIBRATION_ROW | all | %s\n", Describe(r).c_str());
  EXPECT_LT(r.after_m, 1.5 * kNoiseFloor) << Describe(r);
  EXPECT_LT(r.after_m, 0.25 * r.before_m) << Describe(r);
}

// The example rig's effect `name` alone, made large enough to stand clear
// of the tracker's noise (the example's periodic error, thermal drift and
// stiff drive loop are realistic but, alone, barely above it).
RigEffects Alone(calibration::Effect effect) {
  RigEffects e = OnlyEffect(LoadRigEffects(Config()), effect);
  for (double& v : e.leg_offset.offset_m) v *= 3.0;
  for (double& v : e.periodic_lead_error.amplitude_m) v = 12e-6;
  e.thermal_drift.heating_K_per_m = 6.0;
  if (effect == calibration::Effect::kServoLag) {
    e.servo_lag.bandwidth_hz = 12.0;  // a soft loop without integral action
    e.servo_lag.integral_time_s = 0.0;
  }
  return e;
}

// Each effect alone against the rig's own physics of it: the correction
// that compensates it. Alone and small, leg offsets and compliance can be
// `ambiguous` with a neighbour (frame-like signatures), so the model is
// applied as an operator would with --apply-ambiguous.
class CalibrationOfOneEffect : public testing::TestWithParam<calibration::Effect> {};

TEST_P(CalibrationOfOneEffect, ClosesItsOwnGap) {
  const std::string name = calibration::EffectName(GetParam());
  const LoopResult r = CloseTheLoop(Alone(GetParam()), name, true);
  std::printf("CALIBRATION_ROW | %s | %s\n", name.c_str(), Describe(r).c_str());
  EXPECT_NE(r.calibration.find(name), std::string::npos) << Describe(r);
  EXPECT_LT(r.after_m, 1.5 * kNoiseFloor) << Describe(r);
  // The effect alone must stand clear of the noise, or the test could not
  // tell a working correction from none.
  EXPECT_GT(r.before_m, 1.5 * kNoiseFloor) << Describe(r);
  // What stands above the noise (RMS in quadrature) shrinks by 80% or more.
  EXPECT_GT(GapShrink(r.before_m, r.after_m, kNoiseFloor), 0.8) << Describe(r);
}

// A mast carrying the reflector that sways at 5 Hz under the platform's
// acceleration (the example rig's stiff drive loop beside it). The rig
// drives its sway by the platform's own acceleration, so the legs that
// cancel it change what drives it: the calibration must apply the mode's
// inverse (mass 1 − g, calibration.h), not the sway the diagnosis fitted.
TEST(CalibrationLoop, AStructuralModeIsCancelledByTheLegs) {
  RigEffects e = OnlyEffect(LoadRigEffects(Config()), calibration::Effect::kServoLag);
  e.structural_resonance.enabled = true;
  e.structural_resonance.frequency_hz = 5.0;
  e.structural_resonance.damping = 0.03;
  e.structural_resonance.gain = Vector3(0.4, 0.3, 0.1);
  const LoopResult r = CloseTheLoop(e, "structural_resonance");
  std::printf("CALIBRATION_ROW | structural_resonance | %s\n", Describe(r).c_str());
  EXPECT_NE(r.calibration.find("structural_resonance"), std::string::npos) << Describe(r);
  EXPECT_GT(r.before_m, 3.0 * kNoiseFloor) << Describe(r);
  EXPECT_LT(r.after_m, 1.5 * kNoiseFloor) << Describe(r);
}

INSTANTIATE_TEST_SUITE_P(ExampleRig, CalibrationOfOneEffect,
                         testing::ValuesIn(EnabledEffects(LoadRigEffects(Config()))),
                         [](const testing::TestParamInfo<calibration::Effect>& p) {
                           return std::string(calibration::EffectName(p.param));
                         });

}  // namespace
}  // namespace edsp::gap
