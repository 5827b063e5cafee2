// edsp-rig's cycle: what it reports stamped t is the platform at t (the
// state the previous cycle's physics reached), as the offline stack stamps
// it; a report that ran a cycle ahead of its stamp looks, to the diagnosis,
// like a tracker whose clock leads the controller's by that cycle.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/node/build_paths.h"

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

// The rig of config/huang2021-rig-effects.toml: its drives a torque-limited
// servo with integral action, its legs compliant under 800 kg.
RigParameters RigWithEffects() {
  const std::string path = SourcePath("config/huang2021-rig-effects.toml");
  RigParameters p = IdealRig(LoadConfigFile(path));
  p.effects = LoadRigEffects(path);
  p.tracker.rate_hz = 1000.0;
  return p;
}

// The planner's command for cycle k, stamped at its tick, 500 µs before the
// rig's cycle k: every motor accelerating from rest.
DriveCommand CommandFor(int k) {
  const double t = 1e-3 * k;
  DriveCommand c;
  c.enable = true;
  c.setpoint.utime = kStart + 1000 * k - 500;
  c.setpoint.motor_angle_rad.fill(0.5 * 400.0 * t * t);
  c.setpoint.motor_velocity_rad_s.fill(400.0 * t);
  return c;
}

// What a rig woken on time every cycle reports, given the planner's command
// of each.
std::vector<RigCycleReport> ReportsOnTime(int cycles) {
  VirtualRig rig(RigWithEffects());
  RigCycle cycle(&rig, 1e-3, 2.5e-3);
  std::vector<RigCycleReport> reports;
  for (int k = 0; k < cycles; ++k) {
    const std::vector<RigCycleReport>& r = cycle.Wake(kStart + 1000 * k + 20, {CommandFor(k)});
    reports.insert(reports.end(), r.begin(), r.end());
  }
  return reports;
}

// Real hardware's time does not stop when its emulator's host does: a wake
// 13 cycles late replays them, each reported at its own instant, with the
// commands that came meanwhile, and the platform is where a rig woken on
// time put it. A rig that ran one cycle per wake would report, after the
// stall, the platform of 13 ms ago, millimetres off.
TEST(RigCycle, ALateWakeReplaysTheCyclesItMissedAsARigWokenOnTime) {
  const std::vector<RigCycleReport> expected = ReportsOnTime(200);
  VirtualRig late_rig(RigWithEffects());
  RigCycle late(&late_rig, 1e-3, 2.5e-3);
  std::vector<RigCycleReport> got;
  std::vector<DriveCommand> queued;
  for (int k = 0; k < 200; ++k) {
    const std::int64_t grid = kStart + 1000 * k;
    queued.push_back(CommandFor(k));
    if (k >= 120 && k < 133) continue;  // the late rig's host stalls for 13 cycles
    const std::vector<RigCycleReport>& b = late.Wake(grid + (k == 133 ? 700 : 20), queued);
    got.insert(got.end(), b.begin(), b.end());
    queued.clear();
  }
  ASSERT_EQ(got.size(), expected.size());
  double moved = 0.0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    ASSERT_EQ(got[k].utime, expected[k].utime) << "cycle " << k;
    ASSERT_EQ(got[k].tracker.utime, got[k].utime) << "cycle " << k;
    for (int i = 0; i < 3; ++i) {
      ASSERT_NEAR(got[k].tracker.point_m[i], expected[k].tracker.point_m[i], 1e-9) << "cycle " << k;
      moved = std::max(moved, std::abs(got[k].tracker.point_m[i] - got[0].tracker.point_m[i]));
    }
  }
  EXPECT_GT(moved, 0.01);  // the platform ran a centimetre, not stood
  EXPECT_EQ(got.back().utime, kStart + 199 * 1000 + 20);
}

// When the whole host pauses, the controller stalls with the emulator: no
// command came for the cycles the emulator missed. The drives take the
// command between the last and the next to come, as a real rig's
// controller, which would not have stalled, would have sent, so the
// platform runs on as if nothing had stalled; an emulator that woke before
// its controller waits for it. `rig_first`: the emulator wakes first after
// the pause, a cycle before the controller's next command. `rewrite`: the
// bridge, waking, first re-writes its last command with the feed-forward
// dropped (its lapse), under the old stamp.
double FurthestFromARigThatNeverPaused(bool rig_first, bool rewrite = false) {
  const std::vector<RigCycleReport> expected = ReportsOnTime(200);
  VirtualRig paused_rig(RigWithEffects());
  RigCycle paused(&paused_rig, 1e-3, 2.5e-3);
  std::vector<RigCycleReport> got;
  std::vector<DriveCommand> queued;
  for (int k = 0; k < 200; ++k) {
    const std::int64_t grid = kStart + 1000 * k;
    if (k >= 120 && k < 136) continue;  // planner, bridge and rig all paused for 16 cycles
    if (rewrite && k == 136) {
      DriveCommand lapsed = CommandFor(119);
      lapsed.setpoint.motor_velocity_rad_s.fill(0.0);
      queued.push_back(lapsed);
    }
    if (!(rig_first && k == 136)) queued.push_back(CommandFor(k));
    const std::vector<RigCycleReport>& b = paused.Wake(grid + 20, queued);
    EXPECT_EQ(b.empty(), rig_first && k == 136) << "cycle " << k;  // it waited for its controller
    got.insert(got.end(), b.begin(), b.end());
    queued.clear();
    if (rig_first && k == 136) queued.push_back(CommandFor(k));  // came just after the wake
  }
  EXPECT_EQ(got.size(), expected.size());
  double furthest = 0.0;
  for (std::size_t k = 0; k < std::min(got.size(), expected.size()); ++k) {
    EXPECT_EQ(got[k].utime, expected[k].utime) << "cycle " << k;
    for (int i = 0; i < 3; ++i) {
      furthest = std::max(furthest, std::abs(got[k].tracker.point_m[i] - expected[k].tracker.point_m[i]));
    }
  }
  return furthest;
}

// On time, a command stamped 520 µs before its cycle runs on along its
// feed-forward (AtCycleStart) without the parabola's curvature, so the two
// rigs differ by a few micrometres through the pause. With the drives
// braking instead: 2 mm.
TEST(RigCycle, AStallOfTheWholeHostIsBridgedAsIfTheControllerHadNotStalled) {
  EXPECT_LT(FurthestFromARigThatNeverPaused(false), 10e-6);
}

TEST(RigCycle, AnEmulatorThatWakesBeforeItsControllerAfterAPauseWaitsForIt) {
  EXPECT_LT(FurthestFromARigThatNeverPaused(true), 10e-6);
}

TEST(RigCycle, TheBridgesLapseAfterAPauseIsNotReplayedAsACommandOfItsOldInstant) {
  EXPECT_LT(FurthestFromARigThatNeverPaused(false, true), 10e-6);
  EXPECT_LT(FurthestFromARigThatNeverPaused(true, true), 10e-6);
}

// A controller that never comes back (a bridge killed during the pause) is
// waited for 5 ms only: then the missed cycles run, the drives holding.
TEST(RigCycle, AControllerThatDoesNotComeBackIsWaitedForFiveMillisecondsOnly) {
  VirtualRig rig(RigWithEffects());
  RigCycle cycle(&rig, 1e-3, 2.5e-3);
  for (int k = 0; k < 10; ++k) ASSERT_EQ(cycle.Wake(kStart + 1000 * k + 20, {CommandFor(k)}).size(), 1u);
  const std::int64_t woke = kStart + 20'000 + 20;  // ten cycles late, and no command since
  std::int64_t now = woke;
  int waited = 0;
  std::size_t ran = 0;
  while ((ran = cycle.Wake(now, {}).size()) == 0) {
    ++waited;
    now += 1000;
  }
  EXPECT_EQ(waited, 6);                              // the wakes 0..5 ms after the late one
  EXPECT_EQ(ran, 17u);                               // then cycles 10 to 26: every one since the last on time
  EXPECT_EQ(cycle.Wake(now + 1000, {}).size(), 1u);  // and on time again
  // The controller gone, a later late wake waits for nothing: its stamps no
  // longer say which cycle had which command, and the missed time is lost.
  EXPECT_EQ(cycle.Wake(now + 5300, {}).size(), 1u);
  EXPECT_EQ(cycle.Wake(now + 6020, {}).size(), 1u);
}

// Commands stamped by another host's clock, ahead or behind: a late wake
// cannot tell which missed cycle had which, so it loses the missed time and
// runs one cycle with the newest, never waiting; on time again after it.
TEST(RigCycle, StampsOnAnotherHostsClockLoseTheMissedTimeAndNeverWait) {
  for (const std::int64_t offset : {-8000, 5000}) {
    VirtualRig rig(RigWithEffects());
    RigCycle cycle(&rig, 1e-3, 2.5e-3);
    auto command = [&](int k) {
      DriveCommand c = CommandFor(k);
      c.setpoint.utime += offset;
      return c;
    };
    for (int k = 0; k < 10; ++k) ASSERT_EQ(cycle.Wake(kStart + 1000 * k + 20, {command(k)}).size(), 1u);
    std::vector<DriveCommand> queued;
    for (int k = 10; k < 16; ++k) queued.push_back(command(k));
    EXPECT_EQ(cycle.Wake(kStart + 15'300, queued).size(), 1u) << offset;
    EXPECT_EQ(cycle.Wake(kStart + 16'020, {command(16)}).size(), 1u) << offset;
  }
}

// A watchdog that trips in a missed cycle and clears in the wake's own is
// reported by each cycle as it was then: tripped, then commanded again.
TEST(RigCycle, EachCycleOfAWakeReportsTheWatchdogAsItWasThen) {
  VirtualRig rig(RigWithEffects());
  RigCycle cycle(&rig, 1e-3, 2.5e-3, 100);
  for (int k = 0; k < 10; ++k) ASSERT_EQ(cycle.Wake(kStart + 1000 * k + 20, {CommandFor(k)}).size(), 1u);
  // The controller fell silent for 60 ms (longer than a gap the drives are
  // given a command between), the emulator with it; then one command.
  const std::vector<RigCycleReport>& reports = cycle.Wake(kStart + 70'020, {CommandFor(70)});
  ASSERT_EQ(reports.size(), 61u);
  std::vector<std::size_t> changed;
  for (std::size_t k = 0; k < reports.size(); ++k) {
    if (reports[k].watchdog_changed) changed.push_back(k);
  }
  ASSERT_EQ(changed.size(), 2u);
  EXPECT_TRUE(reports[changed[0]].watchdog_tripped);
  EXPECT_GT(reports[changed[0]].since_command_s, 0.02);
  EXPECT_LT(changed[0], 30u);
  EXPECT_EQ(changed[1], 60u);
  EXPECT_FALSE(reports[changed[1]].watchdog_tripped);
}

// The command between two: on the parabola that leaves the first along its
// feed-forward and reaches the second, whose feed-forward is not used.
TEST(RigCycle, TheCommandBetweenTwoIsTheParabolaFromTheFirstsFeedForwardToTheSecond) {
  DriveSetpoint from, to;
  from.utime = kStart;
  to.utime = kStart + 10'000;
  for (std::size_t i = 0; i < 6; ++i) {
    from.motor_angle_rad[i] = 1.0 + static_cast<double>(i);
    from.motor_velocity_rad_s[i] = 30.0;
    to.motor_angle_rad[i] = from.motor_angle_rad[i] + 30.0 * 0.01 + 0.5 * 200.0 * 0.01 * 0.01;  // 200 rad/s²
    to.motor_velocity_rad_s[i] = 1e6;                                                           // a rejoin's
  }
  for (std::int64_t dt : {0, 2500, 7000, 10'000}) {
    const DriveSetpoint at = CommandBetween(from, to, kStart + dt);
    const double t = static_cast<double>(dt) * 1e-6;
    EXPECT_EQ(at.utime, kStart + dt);
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_NEAR(at.motor_angle_rad[i], from.motor_angle_rad[i] + 30.0 * t + 100.0 * t * t, 1e-12) << dt;
      EXPECT_NEAR(at.motor_velocity_rad_s[i], 30.0 + 200.0 * t, 1e-9) << dt;
    }
  }
}

// The wake's own cycle takes the newest command whatever its stamp (another
// host's clock may run ahead): only the missed cycles go by stamps.
TEST(RigCycle, TheWakesOwnCycleTakesTheNewestCommandWhateverItsStamp) {
  VirtualRig rig(IdealRig(Huang2021Config())), reference(IdealRig(Huang2021Config()));
  RigCycle cycle(&rig);
  DriveCommand ahead = CommandFor(50);
  ahead.setpoint.utime = kStart + 9000;  // 9 ms ahead of this host
  const std::vector<RigCycleReport>& reports = cycle.Wake(kStart, {ahead});
  ASSERT_EQ(reports.size(), 1u);
  reference.SetTarget(ahead.setpoint, true);
  ASSERT_TRUE(reference.Advance(1e-3));
  EXPECT_EQ(rig.Feedback().motor_angle_rad, reference.Feedback().motor_angle_rad);
  EXPECT_GT(rig.Feedback().motor_angle_rad[0], 0.01);  // it moved towards the command
}

}  // namespace
}  // namespace edsp
