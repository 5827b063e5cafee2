// edsp-rig's cycle: what it reports stamped t is the platform at t (the
// state the previous cycle's physics reached), as the offline stack stamps
// it; a report that ran a cycle ahead of its stamp looks, to the diagnosis,
// like a tracker whose clock leads the controller's by that cycle.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/rig/rig_effects.h"

namespace edsp {
namespace {

constexpr std::int64_t kStart = 1'000'000;

// Every motor at 20 rad/s from home: where it should be at t_s.
DriveSetpoint Moving(double t_s) {
  DriveSetpoint s;
  s.motor_velocity_rad_s.fill(20.0);
  s.motor_angle_rad.fill(20.0 * t_s);
  return s;
}

// Every motor swaying 10 rad at 2 Hz from home (a smooth motion whose
// acceleration the rig's loads see): where it should be at t_s.
DriveSetpoint Swaying(double t_s) {
  constexpr double kAmplitude = 10.0, kOmega = 2.0 * 3.14159265358979 * 2.0;
  DriveSetpoint s;
  s.motor_angle_rad.fill(kAmplitude * std::sin(kOmega * t_s));
  s.motor_velocity_rad_s.fill(kAmplitude * kOmega * std::cos(kOmega * t_s));
  return s;
}

Vector6 PoseOf(const rig_truth_t& truth) {
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = truth.pose[k];
  return q;
}

TEST(RigCycle, AReportStampedTDescribesThePlatformAtT) {
  RigParameters p = IdealRig(Huang2021Config());
  p.tracker.rate_hz = 1000.0;
  VirtualRig live(p), reference(p);
  RigCycle cycle(&live);
  const Vector6 home = reference.true_pose().ToVector();
  for (int k = 0; k < 50; ++k) {
    const std::int64_t now = kStart + 1000 * k;
    const DriveSetpoint command = Moving(1e-3 * (k + 1));
    const RigCycleReport report = cycle.Step(now, &command, true);
    // The reference has advanced exactly k cycles: the state at `now`.
    const Vector6 expected = reference.true_pose().ToVector();
    ASSERT_EQ(report.truth.utime, now);
    ASSERT_LT((PoseOf(report.truth) - expected).norm(), 1e-12) << "cycle " << k;
    ASSERT_TRUE(report.tracker_due) << k;
    const Vector3 a = reference.true_model().ObservationPoint(reference.true_pose());
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(report.tracker.point_m[i], a(i), 1e-12) << k;
    ASSERT_EQ(report.tracker.utime, now);
    for (int i = 0; i < kNumLegs; ++i) {
      ASSERT_EQ(report.feedback.motor_angle_rad[static_cast<std::size_t>(i)],
                reference.Feedback().motor_angle_rad[static_cast<std::size_t>(i)]);
    }
    reference.SetTarget(command, true);
    ASSERT_TRUE(reference.Advance(1e-3));
  }
  // And it moved: the test compares states that differ cycle to cycle.
  EXPECT_GT((reference.true_pose().ToVector() - home).norm(), 1e-3);
}

// A cycle that starts 6 ms late (the emulator descheduled): its report is
// still the platform at its stamp, the drives having followed the last
// command meanwhile, as a reference rig advanced by hand shows; a freeze
// longer than kLongestCatchUpS catches up that much only.
TEST(RigCycle, ALateCycleReportsThePlatformAtItsStampNotWhereTheLastCycleLeftIt) {
  RigParameters p = IdealRig(Huang2021Config());
  p.tracker.rate_hz = 1000.0;
  VirtualRig live(p), reference(p);
  RigCycle cycle(&live, 1e-3, 0.0);
  std::int64_t now = kStart;
  for (int k = 0; k < 10; ++k, now += 1000) {
    const DriveSetpoint command = Moving(1e-3 * (k + 1));
    cycle.Step(now, &command, true);
    reference.SetTarget(command, true);
    ASSERT_TRUE(reference.Advance(1e-3));
  }
  // No cycle for 6 ms: the reference runs on the last command, cycle by cycle.
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(reference.Advance(1e-3));
  now += 5000;
  const RigCycleReport late = cycle.Step(now, nullptr, true);
  EXPECT_EQ(late.truth.utime, now);
  EXPECT_LT((PoseOf(late.truth) - reference.true_pose().ToVector()).norm(), 1e-12);
  const Vector6 before_freeze = reference.true_pose().ToVector();
  ASSERT_TRUE(reference.Advance(1e-3));  // the late cycle's own
  // Frozen 0.5 s: 20 ms are caught up, not 0.5 s.
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(reference.Advance(1e-3));
  now += 500000;
  const RigCycleReport thawed = cycle.Step(now, nullptr, true);
  EXPECT_LT((PoseOf(thawed.truth) - reference.true_pose().ToVector()).norm(), 1e-12);
  EXPECT_FALSE(thawed.physics_failed);
  EXPECT_GT((reference.true_pose().ToVector() - before_freeze).norm(), 1e-6) << "the drives moved meanwhile";
}

// edsp-rig passes each cycle its tick's instant, and a tick comes late or
// not at all on a busy host. With every effect of the shipped effects
// config (compliance's loads come from the platform's acceleration), cycles
// at pseudo-random instants (up to 450 µs after their tick, one in eight
// after 1–3 missed ticks) report, stamped on the physics' own 1 ms clock
// within half a cycle of their `now`, exactly what a reference advanced by
// hand in whole cycles has at that stamp, and never lose the pose.
// Advancing the physics by a late wake's sliver (a 7 µs step after a 1 ms
// one) made those accelerations noise: 0.1 mm of platform and, live, a
// pose lost at every cycle.
TEST(RigCycle, LateAndMissedTicksRunThePhysicsInWholeCyclesOnTheirOwnClock) {
  RigParameters p = IdealRig(Huang2021Config());
  p.effects = LoadRigEffects(std::string(EDSP_SOURCE_DIR) + "/config/huang2021-rig-effects.toml");
  ASSERT_TRUE(p.effects.compliance.enabled);
  VirtualRig live(p), reference(p);
  RigCycle cycle(&live, 1e-3, 0.0);
  std::int64_t reference_utime = kStart;
  std::uint32_t jitter = 12345;
  std::int64_t tick = 0, caught_up = 0;
  for (int k = 0; k < 400; ++k) {
    jitter = jitter * 1103515245u + 12345u;
    if (k > 0 && (jitter >> 4) % 8 == 0) tick += 1 + (jitter >> 12) % 3;  // missed ticks
    const std::int64_t wake = k == 0 ? 0 : static_cast<std::int64_t>((jitter >> 8) % 450);  // the first anchors
    const std::int64_t now = kStart + 1000 * tick + wake;
    ++tick;
    const DriveSetpoint command = Swaying(1e-3 * k);
    const RigCycleReport report = cycle.Step(now, &command, true);
    ASSERT_FALSE(report.physics_failed) << "cycle " << k;
    ASSERT_EQ((report.utime - kStart) % 1000, 0) << "on the physics' clock, cycle " << k;
    ASSERT_LE(std::abs(report.utime - now), 500) << "within half a cycle of the wake, cycle " << k;
    for (; reference_utime < report.utime; reference_utime += 1000, ++caught_up) {
      ASSERT_TRUE(reference.Advance(1e-3));  // on the last command
    }
    ASSERT_LT((PoseOf(report.truth) - reference.true_pose().ToVector()).norm(), 1e-12) << "cycle " << k;
    reference.SetTarget(command, true);
    ASSERT_TRUE(reference.Advance(1e-3));
    reference_utime += 1000;
  }
  EXPECT_GT(caught_up, 10) << "the jitter made cycles that caught up";
}

TEST(RigCycle, TheWatchdogChangeIsReportedOnceEachWay) {
  VirtualRig rig(IdealRig(Huang2021Config()));
  RigCycle cycle(&rig);
  const DriveSetpoint hold = Moving(0.0);
  int changes = 0;
  std::int64_t now = kStart;
  EXPECT_FALSE(cycle.Step(now, &hold, true).watchdog_changed);
  for (int k = 0; k < 200; ++k) changes += cycle.Step(now += 1000, nullptr, true).watchdog_changed ? 1 : 0;
  EXPECT_EQ(changes, 1);
  EXPECT_TRUE(rig.watchdog_tripped());
  EXPECT_TRUE(cycle.Step(now += 1000, &hold, true).watchdog_changed);  // commands again
  EXPECT_FALSE(rig.watchdog_tripped());
  EXPECT_FALSE(cycle.Step(now += 1000, &hold, true).watchdog_changed);
}

// A command for an instant 700 µs before the rig's cycle continues along
// its velocity to the cycle's start: the drives follow the setpoints' clock
// whatever the phase between the bridge and them; never beyond the
// interpolation horizon, and a command without a stamp is taken as it is.
TEST(RigCycle, ACommandTakenLateContinuesFromTheInstantItIsFor) {
  DriveSetpoint command = Moving(0.010);
  command.utime = kStart - 700;
  const DriveSetpoint at = AtCycleStart(command, kStart, 0.004);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(at.motor_angle_rad[i], 20.0 * (0.010 + 700e-6), 1e-12);
  EXPECT_EQ(at.utime, kStart);
  command.utime = kStart - 60'000;  // stale: at most the horizon
  EXPECT_NEAR(AtCycleStart(command, kStart, 0.004).motor_angle_rad[0], 20.0 * (0.010 + 0.004), 1e-12);
  command.utime = kStart + 500;  // not yet due (another host's clock): as it is
  EXPECT_EQ(AtCycleStart(command, kStart, 0.004).motor_angle_rad[0], 20.0 * 0.010);
  command.utime = 0;
  EXPECT_EQ(AtCycleStart(command, kStart, 0.004).motor_angle_rad[0], 20.0 * 0.010);

  // Through the cycle: the rig's drives take the continued target.
  VirtualRig live(IdealRig(Huang2021Config())), reference(IdealRig(Huang2021Config()));
  RigCycle cycle(&live, 1e-3, 0.004);
  command.utime = kStart - 700;
  cycle.Step(kStart, &command, true);
  reference.SetTarget(AtCycleStart(command, kStart, 0.004), true);
  ASSERT_TRUE(reference.Advance(1e-3));
  EXPECT_EQ(live.Feedback().motor_angle_rad[0], reference.Feedback().motor_angle_rad[0]);
}

}  // namespace
}  // namespace edsp
