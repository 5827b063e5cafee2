// edsp's calibration closed on the blind rig (blindrig/), whose physics
// share no code with the model that makes the calibration: a model of the
// rig's true effects lands it on the nominal model, and on a whole rig
// (every static effect class at once, a heavy payload) the model fitted on
// the six motions meets the calibration target on held-out motions.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/gap/blind_closed_loop.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/report.h"
#include "edsp/gap/rig_scenarios.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/payload_rating.h"
#include "scratch_dir.h"

namespace edsp::gap {
namespace {

PaperMotionOptions BenchmarkMotions() {
  PaperMotionOptions paper;
  paper.stops = 5;
  paper.dwell_s = 0.5;
  paper.max_speed_m_s = 0.25;
  paper.max_speed_rad_s = 0.5;
  return paper;
}

// The blind rig at the calibration benchmark's speeds and dwells, running
// `motions` (edsp's planned ones sampled).
blind::BlindRigSetup BenchmarkSetup(const std::vector<std::string>& motions) {
  const PaperMotionOptions paper = BenchmarkMotions();
  blind::BlindRigSetup setup = blind::SetupFromConfig(Huang2021Config());
  setup.limits.stops = paper.stops;
  setup.limits.dwell_s = paper.dwell_s;
  setup.limits.linear_speed_m_s = paper.max_speed_m_s;
  setup.limits.angular_speed_rad_s = paper.max_speed_rad_s;
  return WithMotions(setup, PlatformModel(Huang2021Config()), paper, motions);
}

// Fitted on `fit` motions, diagnosed blind, the saved model applied on Ly,
// Rx and M3 (the blind rig's own): the closed loop's score.
MotionCheck CalibrateOn(const blind::BlindScenario& rig, const std::vector<std::string>& fit, const std::string& dir) {
  const PlatformModel model(Huang2021Config());
  const BlindRun run = RunBlindRig(BenchmarkSetup(fit), rig, dir + "/fit.csv");
  const Diagnosis d = Diagnose(model, LoadMeasurement(run.csv_path));
  return MeasureBlindClosedLoop(model, BenchmarkSetup({"Ly", "Rx", "M3"}), rig, ModelJson(d), dir);
}

void ExpectTargetMet(const MotionCheck& loop, double noise_m) {
  const double floor = std::sqrt(3.0) * noise_m;
  EXPECT_TRUE(loop.after.rms_m <= 1.5 * floor || Shrink(loop.before.rms_m, loop.after.rms_m) >= 0.9)
      << loop.before.rms_m << " → " << loop.after.rms_m << " m RMS, floor " << floor;
  EXPECT_LE(loop.after.max_m, loop.before.max_m);
  ASSERT_TRUE(loop.predicted.has_value());
  EXPECT_NEAR(loop.after.rms_m, loop.predicted->rms_m, 0.25 * loop.predicted->rms_m);
}

blind::BlindScenario WholeRig() {
  const PlatformModel model(Huang2021Config());
  const double rating = RatePayload(model, RigEffects{}.servo_lag, Vector3(0, 0, kWholeRigComHeightMaxM)).payload_kg;
  return blind::DrawBlindWholeRig(11, 0, rating);
}

std::vector<double> Values(const blind::Vec6& v) { return {v.data(), v.data() + 6}; }

// The rig's leg offsets and lead errors, known exactly and written as the
// model edsp-gap would save: the blind rig, corrected by edsp's
// LegCompensator, lands on the nominal model within the tracker's
// resolution. A sign or a reference (encoder zero, home) that differs
// between edsp's calibration and another rig's physics shows here.
TEST(BlindCalibration, AModelOfTheRigsTrueEffectsLandsItOnTheNominalModel) {
  blind::BlindScenario rig;
  rig.effects.leg_offset_m << 120e-6, -80e-6, 60e-6, -100e-6, 90e-6, -40e-6;
  rig.effects.lead_error << 200e-6, -150e-6, 100e-6, -250e-6, 50e-6, 180e-6;
  rig.tracker.noise_m = 0.0;
  rig.tracker.rate_hz = 100.0;
  const nlohmann::json model = {{"format", "edsp-gap-model/1"},
                                {"effects",
                                 {{{"name", "leg_offset"}, {"theta", Values(rig.effects.leg_offset_m)}},
                                  {{"name", "lead_error"}, {"theta", Values(rig.effects.lead_error)}}}}};
  const std::string dir = test_support::ScratchDir("blind_calibration_exact");
  const MotionCheck loop =
      MeasureBlindClosedLoop(PlatformModel(Huang2021Config()), BenchmarkSetup({"Lz", "Rx", "M3"}), rig, model, dir);
  EXPECT_GT(loop.before.rms_m, 30e-6) << "the effects are there to be corrected";
  std::printf("before %.2f µm RMS, after %.3f µm RMS (%.3f µm largest)\n", loop.before.rms_m * 1e6,
              loop.after.rms_m * 1e6, loop.after.max_m * 1e6);
  EXPECT_LT(loop.after.rms_m, 0.5e-6) << "before " << loop.before.rms_m;
  EXPECT_LT(loop.after.max_m, 2e-6);
}

// A whole rig drawn as the calibration benchmark draws it: fitted on the
// six motions (the blind rig's own), diagnosed blind, the saved model
// applied on held-out motions.
TEST(BlindCalibration, TheSixMotionsCalibrateAWholeRig) {
  const blind::BlindScenario rig = WholeRig();
  ExpectTargetMet(CalibrateOn(rig, {"Lz", "Lx", "Rz", "Ry", "M1", "M2"}, test_support::ScratchDir("blind_six")),
                  rig.tracker.noise_m);
}

// The same rig fitted on edsp's designed calibration motions, planned by
// edsp's planner and played by the blind rig's controller.
TEST(BlindCalibration, TheDesignedMotionsCalibrateAWholeRig) {
  const blind::BlindScenario rig = WholeRig();
  ExpectTargetMet(CalibrateOn(rig, {"calibration"}, test_support::ScratchDir("blind_designed")), rig.tracker.noise_m);
}

}  // namespace
}  // namespace edsp::gap
