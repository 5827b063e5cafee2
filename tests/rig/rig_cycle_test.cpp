// edsp-rig's cycle: what it reports stamped t is the platform at t (the
// state the previous cycle's physics reached), as the offline stack stamps
// it; a report that ran a cycle ahead of its stamp looks, to the diagnosis,
// like a tracker whose clock leads the controller's by that cycle.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_cycle.h"

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

// A master that keeps re-sending its last frame (a drive simulator whose
// fieldbus went quiet) is alive to the drives' watchdog, but its stale
// command is not a new one: the target stops at the interpolation horizon
// as it does for a rig left without commands, instead of starting over along
// the stale feed-forward every cycle (a sawtooth the servo turned into a
// jitter of micrometres while the drives should have been holding).
TEST(RigCycle, AStaleCommandReSentEveryCycleHoldsAsOneThatStopped) {
  RigParameters p = IdealRig(Huang2021Config());
  VirtualRig resent(p), stopped(p);
  RigCycle resent_cycle(&resent, 1e-3, 0.0025), stopped_cycle(&stopped, 1e-3, 0.0025);
  DriveSetpoint command = Moving(0.010);
  command.utime = kStart - 300;
  std::int64_t now = kStart;
  resent_cycle.Step(now, &command, true);
  stopped_cycle.Step(now, &command, true);
  const double first = resent.Feedback().motor_angle_rad[0];
  for (int k = 1; k < 60; ++k) {
    now += 1000;
    resent_cycle.Step(now, &command, true);
    stopped_cycle.Step(now, nullptr, true);
    ASSERT_EQ(resent.Feedback().motor_angle_rad, stopped.Feedback().motor_angle_rad) << "cycle " << k;
    ASSERT_FALSE(resent.watchdog_tripped()) << "cycle " << k;
  }
  EXPECT_TRUE(stopped.watchdog_tripped());
  // It ran on along the feed-forward for the horizon, and stood there.
  EXPECT_NEAR(resent.Feedback().motor_angle_rad[0], 20.0 * (0.010 + 300e-6 + 0.004), 1e-6);  // the servo settled on it
  EXPECT_GT(resent.Feedback().motor_angle_rad[0], first);
  // A new command (another stamp) is taken as one, and held the same way.
  command = Moving(0.020);
  command.utime = now;
  for (int k = 0; k < 60; ++k) resent_cycle.Step(now += 1000, &command, true);
  EXPECT_NEAR(resent.Feedback().motor_angle_rad[0], 20.0 * (0.020 + 0.001 + 0.004), 1e-6);
}

}  // namespace
}  // namespace edsp
