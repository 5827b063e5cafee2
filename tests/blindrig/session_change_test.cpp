// A rig that changes during a session, on data from the independently
// written rig: one leg's length stepping, the tracker's stand knocked. Each
// is an event (when, what, how much), the diagnosis is of the rig after it,
// and a step is never taken for a drift, nor a drift for a step. A rig that
// did not change has no event, whatever else it has.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/report.h"

namespace edsp::blind {
namespace {

const std::vector<std::string> kMotions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};

BlindRigSetup SessionSetup() {
  BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  setup.motions = kMotions;
  return setup;
}

// The session's length as the blind rig runs it (a second between motions).
double SessionSeconds() {
  double total = 0.0;
  for (const std::string& name : kMotions) total += MotionNamed(SessionSetup(), name).duration_s() + 1.0;
  return total;
}

gap::Diagnosis DiagnoseSession(const BlindEffects& effects, unsigned seed = 5, bool encoders = true) {
  TrackerOptions tracker;
  tracker.rate_hz = 100.0;
  tracker.noise_m = 10e-6;
  tracker.seed = seed;
  tracker.encoders = encoders;
  const gap::MeasurementData data =
      gap::ParseMeasurementCsv(GenerateMeasurementCsv(SessionSetup(), effects, tracker), "blind");
  return gap::Diagnose(PlatformModel(Huang2021Config()), data);
}

bool Selected(const gap::Diagnosis& d, gap::Effect e) {
  return std::find(d.selected.begin(), d.selected.end(), e) != d.selected.end();
}

// `ev` is the leg step drawn into `e`: that leg, within 1 s, sized within 20%.
void ExpectTheLegsStep(const gap::ChangeEvent& ev, const BlindEffects& e) {
  EXPECT_EQ(ev.kind, gap::ChangeKind::kLegLength) << gap::DescribeEvent(ev);
  EXPECT_EQ(ev.leg, e.change_leg) << gap::DescribeEvent(ev);
  EXPECT_LE(std::abs(ev.time_s - e.change_time_s), 1.0) << gap::DescribeEvent(ev);
  EXPECT_LE(std::abs(ev.size(0) - e.change_m), 0.2 * std::abs(e.change_m)) << gap::DescribeEvent(ev);
}

// A leg's step of `size_m` at `share` of the session beside a drive loop of
// `loop_hz` recorded without encoders.
BlindEffects StepBesideAnUnrecordedLoop(double loop_hz, double share, int leg, double size_m) {
  BlindEffects e;
  e.servo_bandwidth_hz = loop_hz;
  e.change_time_s = share * SessionSeconds();
  e.change_leg = leg;
  e.change_m = size_m;
  return e;
}

// A coupling slips in the middle of a motion: leg 4 is 80 µm longer from then on.
TEST(SessionChanges, AStepInOneLegIsAnEventAtItsTimeOfItsSize) {
  BlindEffects e;
  e.change_time_s = 0.55 * SessionSeconds();
  e.change_leg = 3;
  e.change_m = 80e-6;
  const gap::Diagnosis d = DiagnoseSession(e);
  ASSERT_EQ(d.changes.events.size(), 1u) << gap::ChangesText(d);
  const gap::ChangeEvent& ev = d.changes.events.front();
  ExpectTheLegsStep(ev, e);
  EXPECT_LE(std::abs(ev.size(0) - e.change_m), 5.0 * ev.sigma(0)) << gap::DescribeEvent(ev);
  // The rig after the change has leg 4 longer than nominal: a leg offset,
  // never a drift.
  EXPECT_FALSE(Selected(d, gap::Effect::kThermalDrift)) << gap::ChangesText(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.5 * d.noise_floor_rms_m) << d.unexplained_note;
}

// The same beside effects the rig has all session: they are named as
// before, the step as an event, and the leg's length after it as the
// offset a calibration applies.
TEST(SessionChanges, AStepBesideTheRigsOwnEffectsLeavesThemNamed) {
  BlindEffects e;
  e.lead_error << 300e-6, -200e-6, 150e-6, -250e-6, 200e-6, -100e-6;
  e.change_time_s = 0.3 * SessionSeconds();
  e.change_leg = 1;
  e.change_m = -60e-6;
  const gap::Diagnosis d = DiagnoseSession(e, 7);
  ASSERT_EQ(d.changes.events.size(), 1u) << gap::ChangesText(d);
  ExpectTheLegsStep(d.changes.events.front(), e);
  EXPECT_TRUE(Selected(d, gap::Effect::kLeadError)) << gap::ChangesText(d);
  EXPECT_FALSE(Selected(d, gap::Effect::kThermalDrift));
  EXPECT_LT(d.holdout_after.rms_m, 1.5 * d.noise_floor_rms_m) << d.unexplained_note;
}

// The same step on a rig whose drive loop is soft (12 Hz) and unrecorded
// (no encoder columns): servo_lag's terms leave the loop's millimetres a
// misfit that varies block by block along every leg, but the step stands
// far above it, so it is one change beside that structure, not fitted
// into it.
TEST(SessionChanges, AStepBesideASoftUnrecordedDriveLoopIsStillAnEvent) {
  const BlindEffects e = StepBesideAnUnrecordedLoop(12.0, 0.45, 0, -60e-6);
  const gap::Diagnosis d = DiagnoseSession(e, 5, false);
  ASSERT_EQ(d.changes.events.size(), 1u) << gap::ChangesText(d);
  ExpectTheLegsStep(d.changes.events.front(), e);
  EXPECT_TRUE(Selected(d, gap::Effect::kServoLag)) << gap::ChangesText(d);
}

// A leg's step beside a 22 Hz drive loop recorded without encoders: the
// loop's misfit along the leg widens that leg's noise more than the
// frame's, so the tracker's six columns, which mimic most of the step,
// stand further past their bar; of two steps at one instant that remove
// the same error, the one of fewer columns is the change.
TEST(SessionChanges, ALegsStepBesideAnUnrecordedLoopIsTheLegsNotTheTrackers) {
  const BlindEffects e = StepBesideAnUnrecordedLoop(22.0, 0.67, 5, -60e-6);
  const gap::Diagnosis d = DiagnoseSession(e, 5, false);
  ASSERT_FALSE(d.changes.events.empty()) << gap::ChangesText(d);
  ExpectTheLegsStep(d.changes.events.front(), e);  // the largest, found first
  for (const gap::ChangeEvent& other : d.changes.events) {
    EXPECT_TRUE(other.kind != gap::ChangeKind::kLegLength || other.leg == 5) << gap::DescribeEvent(other);
  }
}

// The tracker's stand knocked while the platform rises straight up (the
// session's first motion): the points before it lie on a line, so the
// frame's turn about that line cannot be sized, and the step is turned
// away. A leg's step at the same instant mimics part of it, and is that
// step's shadow: never a leg's event.
TEST(SessionChanges, ATrackerKnockedDuringAVerticalMotionIsNeverALegsEvent) {
  BlindEffects e;
  e.change_time_s = 0.6 * MotionNamed(SessionSetup(), "Lz").duration_s();
  e.change_tracker << 50e-6, 40e-6, -30e-6, 20e-6, -20e-6, 25e-6;
  const gap::Diagnosis d = DiagnoseSession(e);
  for (const gap::ChangeEvent& ev : d.changes.events)
    EXPECT_EQ(ev.kind, gap::ChangeKind::kTrackerFrame) << gap::DescribeEvent(ev);
}

// The tracker's stand knocked: an event of the tracker, no leg's.
TEST(SessionChanges, AKnockedTrackerIsAnEventOfTheTrackerNeverOfALeg) {
  BlindEffects e;
  e.change_time_s = 0.45 * SessionSeconds();
  e.change_tracker << 60e-6, -40e-6, 30e-6, 30e-6, 0.0, -40e-6;
  const gap::Diagnosis d = DiagnoseSession(e);
  ASSERT_FALSE(d.changes.events.empty()) << gap::ChangesText(d);
  for (const gap::ChangeEvent& ev : d.changes.events) {
    EXPECT_EQ(ev.kind, gap::ChangeKind::kTrackerFrame) << gap::DescribeEvent(ev);
    EXPECT_LE(std::abs(ev.time_s - e.change_time_s), 1.0) << gap::DescribeEvent(ev);
  }
  EXPECT_TRUE(d.selected.empty()) << gap::ChangesText(d);
  EXPECT_LT(d.holdout_after.rms_m, 1.5 * d.noise_floor_rms_m) << d.unexplained_note;
}

// The same knock on a rig whose structure sways at 4.3 Hz: judged beside the
// vocabulary before the mode's frequency is known, the sway left along the
// tracker's signature turned the step away as structure; the search runs
// again beside the mode, and the knock is an event of its time and size.
TEST(SessionChanges, AKnockedTrackerBesideASwayingStructureIsStillAnEvent) {
  BlindEffects e;
  e.resonance_hz = 4.3;
  e.resonance_damping = 0.028;
  e.resonance_gain = 0.4;
  e.change_time_s = 0.45 * SessionSeconds();
  e.change_tracker << 60e-6, -40e-6, 30e-6, 30e-6, 0.0, -40e-6;
  const gap::Diagnosis d = DiagnoseSession(e);
  ASSERT_EQ(d.changes.events.size(), 1u) << gap::ChangesText(d);
  const gap::ChangeEvent& ev = d.changes.events.front();
  EXPECT_EQ(ev.kind, gap::ChangeKind::kTrackerFrame) << gap::DescribeEvent(ev);
  EXPECT_LE(std::abs(ev.time_s - e.change_time_s), 1.0) << gap::DescribeEvent(ev);
  EXPECT_NEAR(ev.size.tail<3>().norm(), e.change_tracker.tail<3>().norm(), 0.2 * e.change_tracker.tail<3>().norm())
      << gap::DescribeEvent(ev);
  EXPECT_NEAR(d.changes.structural_mode_hz, 4.3, 0.3);
  EXPECT_TRUE(Selected(d, gap::Effect::kStructuralResonance)) << gap::ChangesText(d);
}

// A screw warming under power drifts: it is the thermal effect, no event.
TEST(SessionChanges, AThermalDriftIsNeverAStep) {
  BlindEffects e;
  e.alpha_per_K = 11.5e-6;
  e.heating_K_per_s = 0.02;
  e.thermal_tau_s = 600.0;
  const gap::Diagnosis d = DiagnoseSession(e);
  EXPECT_TRUE(d.changes.events.empty()) << gap::ChangesText(d);
  EXPECT_TRUE(Selected(d, gap::Effect::kThermalDrift)) << gap::ChangesText(d);
}

// The tracker's stand settling drifts too, on the tracker's side: no event.
TEST(SessionChanges, ATrackerStandSettlingIsNeverAStep) {
  BlindEffects e;
  e.stand_drift_m_per_s << 0.3e-6, -0.25e-6, 0.1e-6;
  e.stand_settle_s = 400.0;
  const gap::Diagnosis d = DiagnoseSession(e);
  EXPECT_TRUE(d.changes.events.empty()) << gap::ChangesText(d);
}

// Rigs that did not change, as the blind rig draws them (effect-free, one
// effect, two, one outside the vocabulary): no event. A target re-seated
// before each run did change, on the tracker's side: never a leg's event.
TEST(SessionChanges, ARigThatDidNotChangeHasNoEvent) {
  for (int index = 0; index < 5; ++index) {
    const BlindScenario s = DrawBlindScenario(4711, index);
    const gap::MeasurementData data =
        gap::ParseMeasurementCsv(GenerateMeasurementCsv(SessionSetup(), s.effects, s.tracker), "blind");
    const gap::Diagnosis d = gap::Diagnose(PlatformModel(Huang2021Config()), data);
    const bool reseated = s.effects.target_reseat_m > 0.0;
    for (const gap::ChangeEvent& ev : d.changes.events) {
      EXPECT_TRUE(reseated && ev.kind == gap::ChangeKind::kTrackerFrame)
          << "scenario " << index << " (" << s.description << "): " << gap::DescribeEvent(ev);
    }
  }
}

}  // namespace
}  // namespace edsp::blind
