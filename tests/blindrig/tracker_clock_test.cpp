// The tracker's clock against the controller's, on data from the
// independently written rig: a clock offset is found from the encoder
// columns and removed like the frame, never named as an effect; a servo lag
// beside it is still found; without encoders it is not estimated.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/diagnosis/diagnose.h"

namespace edsp::blind {
namespace {

gap::Diagnosis DiagnoseWithClock(const BlindEffects& effects, double offset_s, bool encoders) {
  BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  setup.motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
  TrackerOptions tracker;
  tracker.rate_hz = 100.0;
  tracker.noise_m = 10e-6;
  tracker.seed = 11;
  tracker.encoders = encoders;
  tracker.time_offset_s = offset_s;
  return gap::Diagnose(PlatformModel(Huang2021Config()),
                       gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, effects, tracker), "blind"));
}

bool NothingIdentified(const gap::Diagnosis& d) {
  for (const gap::EffectResult& r : d.effects) {
    if (r.verdict == "identified") return false;
  }
  return true;
}

// Both signs: 3 ms is 0.75 mm at A's 0.25 m/s, far beyond every effect.
TEST(TrackerClock, AnOffsetIsFoundFromTheEncodersAndIsNoEffect) {
  for (double offset_s : {3e-3, -2e-3}) {
    const gap::Diagnosis d = DiagnoseWithClock({}, offset_s, true);
    ASSERT_TRUE(d.time_offset.estimated) << d.time_offset.note;
    EXPECT_TRUE(d.time_offset.applied) << d.time_offset.note;
    EXPECT_LT(std::abs(d.time_offset.offset_s - offset_s), 5.0 * d.time_offset.sigma_s) << d.time_offset.note;
    EXPECT_EQ(d.conclusion, "none") << d.unexplained_note;
    EXPECT_TRUE(NothingIdentified(d));
    EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m);
  }
}

TEST(TrackerClock, ClocksThatAgreeAreLeftAlone) {
  const gap::Diagnosis d = DiagnoseWithClock({}, 0.0, true);
  ASSERT_TRUE(d.time_offset.estimated);
  EXPECT_FALSE(d.time_offset.applied) << d.time_offset.note;
  EXPECT_EQ(d.conclusion, "none");
}

// The drives' lag lies between command and encoder, the clock's between the
// tracker and both: each is found for what it is.
TEST(TrackerClock, AServoLagBesideAnOffsetIsStillTheServos) {
  BlindEffects e;
  e.servo_bandwidth_hz = 15.0;
  const gap::Diagnosis d = DiagnoseWithClock(e, -2e-3, true);
  EXPECT_TRUE(d.time_offset.applied) << d.time_offset.note;
  EXPECT_LT(std::abs(d.time_offset.offset_s + 2e-3), 5.0 * d.time_offset.sigma_s) << d.time_offset.note;
  EXPECT_EQ(d.selected, std::vector<gap::Effect>{gap::Effect::kServoLag});
  for (const gap::EffectResult& r : d.effects) {
    if (r.effect != gap::Effect::kServoLag) continue;
    EXPECT_EQ(r.verdict, "identified") << r.next_measurement;
    EXPECT_TRUE(r.encoder_checked);
    EXPECT_GT(r.encoder_share, 0.9);  // the encoders show the drives' lag
  }
  EXPECT_EQ(d.conclusion, "effects") << d.unexplained_note;
  EXPECT_LT(d.holdout_after.rms_m, 1.2 * d.noise_floor_rms_m);
}

// From the tracker alone an offset and a lag equal on every leg are one
// (docs/diagnosis.md, "Limits"): not estimated, and said so.
TEST(TrackerClock, WithoutEncodersItIsNotEstimated) {
  const gap::Diagnosis d = DiagnoseWithClock({}, 3e-3, false);
  EXPECT_FALSE(d.time_offset.estimated);
  EXPECT_FALSE(d.time_offset.applied);
  EXPECT_NE(d.time_offset.note.find("without encoder columns"), std::string::npos) << d.time_offset.note;
}

}  // namespace
}  // namespace edsp::blind
