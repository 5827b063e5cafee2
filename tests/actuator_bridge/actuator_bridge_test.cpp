// The bridge forwards only what it can validate and holds on stale input;
// tested against a fake backend that records what the drives were told.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include <limits>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/kinematics/config.h"
#include "recording_backend.h"

namespace edsp {
namespace {

constexpr std::int64_t kStart = 1000000000;

struct Fixture {
  PlatformModel model{Huang2021Config()};
  RecordingBackend backend;
  ActuatorBridge bridge{model, &backend, Options()};
  static BridgeOptions Options() {
    BridgeOptions o;
    o.session_id = 5;
    return o;
  }
  leg_command_t Command(double dz_m, std::int64_t utime, std::int64_t seq = 1) {
    Pose pose = model.home_pose();
    pose.p_BoMo_B.z() += dz_m;
    const Vector6 lengths = model.CompensatedLengths(pose, PrMode::kSigned);
    leg_command_t c{};
    c.utime = utime;
    c.setpoint_utime = utime;
    c.seq = seq;
    c.session_id = 5;
    for (int i = 0; i < kNumLegs; ++i) c.command_length_m[i] = lengths(i);
    return c;
  }
};

// Commands and cycles every ms, moving up `step_m` per ms from home, for
// `count` ms from *t (advanced). Every command must be accepted.
void MoveUp(Fixture& f, std::int64_t* t, double step_m, int count) {
  fault_t fault;
  leg_state_t state;
  for (int k = 1; k <= count; ++k, *t += 1000) {
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(step_m * k, *t, k), *t, &fault)) << fault.reason;
    f.bridge.Cycle(*t, &state, &fault);
  }
}

// Lengths the drives were told, from their motor angles.
Vector6 WrittenLengths(const Fixture& f) {
  Vector6 l;
  for (int i = 0; i < kNumLegs; ++i) l(i) = f.model.LengthFromMotorAngle(i, f.backend.written.motor_angle_rad[i]);
  return l;
}

// The lengths a command asks for.
Vector6 CommandLengths(const leg_command_t& c) {
  Vector6 l;
  for (int i = 0; i < kNumLegs; ++i) l(i) = c.command_length_m[i];
  return l;
}

// Where the drives take what they were told to be at `utime`: a setpoint
// continued from its own instant along its feed-forward (0: as it is).
Vector6 DrivesTakeAt(const Fixture& f, std::int64_t utime) {
  const DriveSetpoint& w = f.backend.written;
  const double late_s = w.utime != 0 ? static_cast<double>(utime - w.utime) * 1e-6 : 0.0;
  Vector6 l;
  for (int i = 0; i < kNumLegs; ++i) {
    l(i) = f.model.LengthFromMotorAngle(i, w.motor_angle_rad[i] + w.motor_velocity_rad_s[i] * late_s);
  }
  return l;
}

TEST(ActuatorBridge, StartUpHoldIsNotLatched) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  for (int k = 0; k < 100; ++k) f.bridge.Cycle(kStart - 100000 + k * 1000, &state, &fault);
  EXPECT_TRUE(f.bridge.holding());
  EXPECT_FALSE(f.bridge.latched());
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(0.0, kStart), kStart, &fault)) << fault.reason;
}

// A leg state describes the drives when they latched their reading (the
// rig's image: the start of its cycle, most of a cycle before the bridge
// reads it), so the measurement export pairs it with the tracker sample of
// that instant; undated or stale readings are stamped with the read.
TEST(ActuatorBridge, ALegStateIsStampedWithTheInstantItsReadingDescribes) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  f.backend.latched_utime = kStart - 900;  // the rig's cycle 900 µs before this read
  f.bridge.Cycle(kStart, &state, &fault);
  EXPECT_EQ(state.utime, kStart - 900);
  f.backend.latched_utime = 0;  // drives that do not date their reading
  f.bridge.Cycle(kStart + 1000, &state, &fault);
  EXPECT_EQ(state.utime, kStart + 1000);
  f.backend.latched_utime = kStart - 900;  // the same reading, 2.9 ms on: stopped publishing
  f.bridge.Cycle(kStart + 2000, &state, &fault);
  EXPECT_EQ(state.utime, kStart + 2000);
  f.backend.latched_utime = kStart + 3500;  // another host's clock ahead of this one
  f.bridge.Cycle(kStart + 3000, &state, &fault);
  EXPECT_EQ(state.utime, kStart + 3000);
}

TEST(ActuatorBridge, ValidCommandsReachTheDrivesAsMotorAngles) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  for (int k = 1; k <= 100; ++k, t += 1000) {  // 0.1 mm per ms = 0.1 m/s
    const leg_command_t c = f.Command(1e-4 * k, t, k);
    ASSERT_TRUE(f.bridge.HandleCommand(c, t, &fault)) << fault.reason;
    EXPECT_FALSE(f.bridge.Cycle(t, &state, &fault));
    EXPECT_NEAR(f.backend.written.motor_angle_rad[2], f.model.MotorAngleFromLength(2, c.command_length_m[2]), 1e-12);
    EXPECT_EQ(f.bridge.written_setpoint_utime(), c.setpoint_utime);
  }
  // The cycle reads before it writes: the drives' answer to the last command
  // is in the next cycle's state.
  f.bridge.Cycle(t, &state, &fault);
  const leg_command_t last = f.Command(1e-2, t - 1000, 100);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_NEAR(f.backend.written.motor_angle_rad[i], f.model.MotorAngleFromLength(i, last.command_length_m[i]), 1e-9);
    EXPECT_NEAR(state.encoder_length_m[i], last.command_length_m[i], 1e-12);
    EXPECT_GT(f.backend.written.motor_velocity_rad_s[i], 0.0);  // feed-forward while rising
    EXPECT_EQ(state.drive_status[i], leg_state_t::DRIVE_ENABLED);
  }
  EXPECT_EQ(state.command_seq, 100);
  EXPECT_FALSE(f.bridge.holding());
}

// A cyclic fieldbus master sees one Read and then one Write per cycle, and
// nothing in between: commands, refusals, holds, lost drives and re-arms
// only change what the next cycle writes.
TEST(ActuatorBridge, EveryCycleIsOneReadThenOneWriteAndNothingElseTouchesTheDrives) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  f.backend.exchanges.clear();  // the constructor's read of where the drives start
  int cycles = 0;
  auto cycle = [&] {
    f.bridge.Cycle(t, &state, &fault);
    ++cycles;
    t += 1000;
  };
  for (int k = 1; k <= 30; ++k) {  // moving, with a burst of two commands in one cycle
    f.bridge.HandleCommand(f.Command(1e-4 * k, t, k), t, &fault);
    if (k % 10 == 0) f.bridge.HandleCommand(f.Command(1e-4 * k, t, k), t, &fault);
    cycle();
  }
  for (int k = 0; k < 80; ++k) cycle();  // stale: holds and latches
  EXPECT_TRUE(f.bridge.latched());
  f.bridge.HandleCommand(f.Command(0.0, t, 99), t, &fault);  // refused while latched
  f.backend.answering = false;                               // drives lost
  cycle();
  std::string expected;
  for (int k = 0; k < cycles; ++k) expected += "RW";
  EXPECT_EQ(f.backend.exchanges, expected);
  // A re-arm of lost drives resets them (acyclic, between cycles), once.
  EXPECT_TRUE(f.bridge.Rearm());
  f.backend.answering = true;
  cycle();
  EXPECT_EQ(f.backend.exchanges, expected + "XRW");
}

void ExpectRejected(Fixture& f, const leg_command_t& c, FaultCode code, const std::string& text,
                    std::int64_t now = kStart) {
  fault_t fault;
  const DriveSetpoint before = f.backend.written;
  EXPECT_FALSE(f.bridge.HandleCommand(c, now, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(code)) << fault.reason;
  EXPECT_NE(fault.reason.find(text), std::string::npos) << fault.reason;
  leg_state_t state;
  f.bridge.Cycle(now, &state, &fault);
  EXPECT_EQ(f.backend.written.motor_angle_rad, before.motor_angle_rad) << "a refused command moved the drives";
}

TEST(ActuatorBridge, LateOrBurstyDeliveryIsNotMistakenForAJump) {
  // 0.4 m/s of leg motion, planner at 1 kHz, but the commands arrive in bursts
  // of three in one bridge cycle (a late cycle upstream).
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t planner_time = kStart;
  for (int burst = 0; burst < 20; ++burst) {
    const std::int64_t arrival = kStart + burst * 3000;
    for (int k = 0; k < 3; ++k) {
      planner_time += 1000;
      const double dz = 4e-4 * static_cast<double>((planner_time - kStart) / 1000);
      leg_command_t c = f.Command(dz, arrival, 1 + burst * 3 + k);
      c.setpoint_utime = planner_time;
      EXPECT_TRUE(f.bridge.HandleCommand(c, arrival, &fault)) << fault.reason;
    }
    f.bridge.Cycle(arrival, &state, &fault);
  }
  EXPECT_EQ(f.bridge.rejected(), 0);
}

// A planner tick 0.7 ms late, the next on time (setpoints 1.676 ms then
// 0.327 ms apart, as the live planner's were): the drives' velocity
// feed-forward stays the motion's own at every command. Over a whole cycle
// the short step's feed-forward was a third of the speed, a kick the
// servo turned into ±0.4 mm at 0.25 m/s. A repeated stamp keeps the last.
TEST(ActuatorBridge, TheFeedForwardIsTheStepOverThePlannerTimeItTook) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  const double speed = 0.1;  // m/s up
  std::int64_t planner = kStart;
  int seq = 0;
  auto take = [&](std::int64_t setpoint_utime) {
    const double dz = speed * static_cast<double>(setpoint_utime - kStart) * 1e-6;
    leg_command_t c = f.Command(dz, setpoint_utime, ++seq);
    ASSERT_TRUE(f.bridge.HandleCommand(c, setpoint_utime + 200, &fault)) << fault.reason;
    f.bridge.Cycle(setpoint_utime + 300, &state, &fault);
  };
  for (int k = 0; k < 20; ++k) take(planner += 1000);
  // The motor speed of a rise at `speed`: the angle's finite difference.
  const double expected = (f.model.MotorAngleFromLength(0, f.Command(speed * 1e-3, 0).command_length_m[0]) -
                           f.model.MotorAngleFromLength(0, f.Command(0.0, 0).command_length_m[0])) /
                          1e-3;
  ASSERT_GT(expected, 1.0);
  for (std::int64_t gap : {1676, 327, 1000, 1114, 946, 924}) {
    take(planner += gap);
    EXPECT_NEAR(f.backend.written.motor_velocity_rad_s[0], expected, 0.01 * expected)
        << "after a " << gap << " µs step";
  }
  // The same setpoint stamp again (a reordered or repeated setpoint).
  const double before = f.backend.written.motor_velocity_rad_s[0];
  take(planner);
  EXPECT_EQ(f.backend.written.motor_velocity_rad_s[0], before);
}

// A step the jump check lets through (within the legs' top speed over a
// whole cycle) but that 0.3 ms of planner time does not explain: its
// feed-forward stays over the cycle, not three times the legs' top speed.
TEST(ActuatorBridge, AStepTheTimeSinceTheLastSetpointDoesNotExplainGetsNoKick) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  const double vmax = f.model.config().limits.leg_speed_max_m_s;
  std::int64_t t = kStart;
  MoveUp(f, &t, 0.0, 5);                                                     // at rest, the stream running
  const leg_command_t c = f.Command(0.8 * vmax * 1e-3, t - 1000 + 300, 99);  // 0.8 ms worth of top speed in 0.3 ms
  ASSERT_TRUE(f.bridge.HandleCommand(c, t, &fault)) << fault.reason;
  f.bridge.Cycle(t, &state, &fault);
  // The fastest a motor may turn: the legs' top speed as motor angle.
  const double top = (f.model.MotorAngleFromLength(0, f.Command(vmax * 1e-3, 0).command_length_m[0]) -
                      f.model.MotorAngleFromLength(0, f.Command(0.0, 0).command_length_m[0])) /
                     1e-3;
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_LE(std::abs(v), 1.01 * top);
  EXPECT_GT(f.backend.written.motor_velocity_rad_s[0], 0.5 * top);  // and it moves
}

TEST(ActuatorBridge, RefusesForeignNonFiniteOutOfStrokeAndJumpingCommands) {
  Fixture f;
  leg_command_t c = f.Command(0.0, kStart);
  c.session_id = 6;
  ExpectRejected(f, c, FaultCode::kForeignSession, "session 6");
  c = f.Command(0.0, kStart);
  c.command_length_m[2] = std::nan("");
  ExpectRejected(f, c, FaultCode::kNonFinite, "leg 3");
  c = f.Command(0.0, kStart);
  c.command_length_m[1] = 2.6;
  ExpectRejected(f, c, FaultCode::kOutOfStroke, "leg 2");
  ExpectRejected(f, f.Command(0.05, kStart), FaultCode::kJump, "jumps");  // 5 cm in 1 ms
  c = f.Command(0.0, kStart - 60000);
  ExpectRejected(f, c, FaultCode::kStale, "us old");
  EXPECT_EQ(f.bridge.rejected(), 5);
}

// setpoint_utime is the sender's word: any int64 may come, from this
// session or another, while the bridge moves. No arithmetic on it may
// overflow (UBSan in the sanitized stage), and the extremes allow no more
// than the stale limit's step.
TEST(ActuatorBridge, AnyPlannerTimeInACommandIsHandledWithoutOverflow) {
  for (std::int64_t extreme : {std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()}) {
    Fixture f;
    std::int64_t t = kStart;
    MoveUp(f, &t, 1e-5, 20);
    fault_t fault;
    leg_command_t c = f.Command(20e-5, t, 21);
    c.setpoint_utime = extreme;
    c.session_id = 6;
    EXPECT_FALSE(f.bridge.HandleCommand(c, t, &fault));
    EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kForeignSession)) << fault.reason;
    c.session_id = 5;
    EXPECT_TRUE(f.bridge.HandleCommand(c, t, &fault)) << fault.reason;  // no motion: within any step
    c = f.Command(20e-5 + 0.06, t + 1000, 22);                          // 60 mm up: legs beyond the stale limit's 25 mm
    EXPECT_FALSE(f.bridge.HandleCommand(c, t + 1000, &fault));
    EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kJump)) << fault.reason;
  }
}

// The drives' interpolator ran on past the last target and stopped there
// (0.05 rad further on every motor) while the bridge was frozen: where they
// now are.
std::array<double, 6> StopDrivesAhead(Fixture& f) {
  std::array<double, 6> past = f.backend.written.motor_angle_rad;
  for (double& a : past) a += 0.05;
  f.backend.stopped_at = past;
  return past;
}

// One command at home, then 100 ms of silence (the link is gone): latched.
// Returns the time after it.
std::int64_t LatchAtHome(Fixture& f) {
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(0.0, t, 1), t, &fault));
  for (int k = 0; k < 100; ++k, t += 1000) f.bridge.Cycle(t, &state, &fault);
  EXPECT_TRUE(f.bridge.latched());
  return t;
}

TEST(ActuatorBridge, AReArmedBridgeRejoinsAMovedStreamAtTheRejoinSpeed) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = LatchAtHome(f);
  const Vector6 held = WrittenLengths(f);
  f.bridge.Rearm();
  // The planner moved on by 20 mm in z meanwhile, and goes on 0.01 mm per ms.
  const double speed = Fixture::Options().rejoin_speed_m_s;
  const double first_gap = (CommandLengths(f.Command(0.02, t, 2)) - held).cwiseAbs().maxCoeff();
  double gap_left = first_gap, largest_closing = 0.0;
  int k = 0;
  for (; k < 3000 && (k == 0 || f.bridge.rejoining()); ++k, t += 1000) {
    const double dz = 0.02 + 1e-5 * k;
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(dz, t, 2 + k), t, &fault)) << k << ": " << fault.reason;
    f.bridge.Cycle(t, &state, &fault);
    // The gap to the stream closes at the rejoin speed, the stream's motion included.
    const double gap = (CommandLengths(f.Command(dz, t, 2 + k)) - WrittenLengths(f)).cwiseAbs().maxCoeff();
    if (k > 0) largest_closing = std::max(largest_closing, gap_left - gap);
    gap_left = gap;
  }
  EXPECT_FALSE(f.bridge.rejoining()) << "never caught up";
  EXPECT_LE(largest_closing, speed * 1e-3 + 1e-9);                 // never closing faster than the rejoin speed
  EXPECT_GE(k, static_cast<int>(first_gap / (speed * 1e-3)) - 1);  // so it took its time
  // Caught up: the drives follow the stream exactly again.
  ASSERT_TRUE(f.bridge.HandleCommand(f.Command(0.02 + 1e-5 * k, t, 5000), t, &fault)) << fault.reason;
  f.bridge.Cycle(t, &state, &fault);
  const Vector6 expected = [&] {
    leg_command_t c = f.Command(0.02 + 1e-5 * k, t, 5000);
    Vector6 l;
    for (int i = 0; i < kNumLegs; ++i) l(i) = c.command_length_m[i];
    return l;
  }();
  EXPECT_LT((WrittenLengths(f) - expected).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ActuatorBridge, ACommandFromTheFutureMeansTheClocksDisagreeAndIsRefused) {
  Fixture f;
  fault_t fault;
  const std::int64_t t = kStart;
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(0.0, t + 40000, 1), t, &fault)) << fault.reason;  // within the limit
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(0.0, t + 60000, 2), t, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kStale));
  EXPECT_NE(fault.reason.find("60000 us in the future"), std::string::npos) << fault.reason;
  EXPECT_NE(fault.reason.find("clocks"), std::string::npos) << fault.reason;
}

// Commands stop mid-motion: the drives are told the last command's motion,
// continued for 10 ms and then brought to rest with the fastest leg at the
// legs' acceleration limit (never back towards the last command, which
// would be a jerk of its own); then held there, latched, at the stale limit.
TEST(ActuatorBridge, SilenceBringsTheMotionToRestAtTheLegsLimitAndHoldsWithin50ms) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 20);  // 0.1 m/s up
  const Vector6 last = WrittenLengths(f);
  Vector6 before;
  for (int i = 0; i < kNumLegs; ++i) before(i) = f.Command(1e-4 * 19, 0).command_length_m[i];
  const Vector6 speed = (last - before) / 1e-3;  // each leg's, m/s
  const double decel = f.model.config().motion.leg_accel_max_m_s2;
  const double stop_s = speed.cwiseAbs().maxCoeff() / decel;
  int faults = 0;
  std::int64_t hold_at = -1;
  std::vector<Vector6> written = {last};
  for (int k = 0; k < 200; ++k, t += 1000) {  // commands stop; the drives' view of each cycle
    if (f.bridge.Cycle(t, &state, &fault)) {
      ++faults;
      EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kLatched));
      if (hold_at < 0) hold_at = t;
    }
    written.push_back(DrivesTakeAt(f, t));
  }
  // Along the last motion, never back, decelerating at no more than the
  // limit (second differences of what was written each cycle).
  for (std::size_t k = 1; k < written.size(); ++k) {
    for (int i = 0; i < kNumLegs; ++i) {
      EXPECT_GE((written[k](i) - written[k - 1](i)) * speed(i), -1e-12) << "leg " << i + 1 << " went back, cycle " << k;
    }
    if (k >= 2) {
      const Vector6 accel = (written[k] - 2.0 * written[k - 1] + written[k - 2]) / 1e-6;
      EXPECT_LE(accel.cwiseAbs().maxCoeff(), decel * 1.01) << "cycle " << k;
    }
  }
  // At rest where v·(10 ms) + v·T/2 put each leg (closed form).
  const Vector6 expected = last + speed * (timing::kRideThroughS + stop_s / 2.0);
  EXPECT_LT((written.back() - expected).cwiseAbs().maxCoeff(), 1e-7) << (written.back() - expected).transpose();
  EXPECT_GT((written.back() - last).cwiseAbs().maxCoeff(), 5e-4);  // a millimetre on, not held at the command
  EXPECT_EQ(faults, 1);                                            // reported once, not every cycle
  EXPECT_LE(hold_at - (kStart + 19000), 51000);
  EXPECT_TRUE(f.bridge.holding());
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(state.drive_status[0], leg_state_t::DRIVE_HOLDING);
  // Latched: even a command continuing exactly from the hold is refused.
  EXPECT_TRUE(f.bridge.latched());
  const double held_dz = 2e-3 + (expected(0) - last(0)) / speed(0) * 0.1;
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(held_dz, t, 21), t, &fault));
  EXPECT_NE(fault.reason.find("re-arm required"), std::string::npos) << fault.reason;
  EXPECT_NE(fault.reason.find("holding after stale input"), std::string::npos) << fault.reason;
  f.bridge.Rearm();
  // Re-armed: a command continuing from the hold is simply followed.
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(held_dz, t, 22), t, &fault)) << fault.reason;
  EXPECT_FALSE(f.bridge.holding());
  EXPECT_FALSE(f.bridge.rejoining());
}

// A command late by a few cycles (a planner tick missed on a loaded host):
// the drives are told its motion continued, under its own stamp while they
// continue it themselves, then restamped each cycle at the instant it is
// for. The command that comes 5.3 ms after the last finds them where its
// motion put them, where the command's own position (held at rest) was
// half a millimetre behind. Silent longer than 10 ms, they slow down.
TEST(ActuatorBridge, ALateCommandIsContinuedThenSlowedNeverPulledBack) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 5);  // moving up at 0.1 m/s
  const std::int64_t last_utime = t - 1000;
  const auto command = f.backend.written;
  const Vector6 last = WrittenLengths(f);
  EXPECT_GT(std::abs(command.motor_velocity_rad_s[0]), 1.0);
  f.bridge.Cycle(last_utime + 1000, &state, &fault);
  f.bridge.Cycle(last_utime + 2000, &state, &fault);  // late: the command as it was
  EXPECT_EQ(f.backend.written.motor_angle_rad, command.motor_angle_rad);
  EXPECT_EQ(f.backend.written.motor_velocity_rad_s, command.motor_velocity_rad_s);
  EXPECT_EQ(f.backend.written.utime, command.utime);
  f.bridge.Cycle(last_utime + 3000, &state, &fault);  // overdue: restamped, as fast, ahead of the command
  EXPECT_EQ(f.backend.written.utime, command.utime + 3000);
  EXPECT_EQ(f.backend.written.motor_velocity_rad_s, command.motor_velocity_rad_s);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_NEAR(f.backend.written.motor_angle_rad[i] - command.motor_angle_rad[i],
                command.motor_velocity_rad_s[i] * 3e-3, 1e-9)
        << "leg " << i + 1;
  }
  f.bridge.Cycle(last_utime + 4000, &state, &fault);
  f.bridge.Cycle(last_utime + 5000, &state, &fault);
  EXPECT_FALSE(f.bridge.holding());  // not stale yet: the next command just continues
  const leg_command_t next = f.Command(1e-4 * 5 + 0.1 * 5.3e-3, last_utime + 5300, 6);
  Vector6 next_m;
  for (int i = 0; i < kNumLegs; ++i) next_m(i) = next.command_length_m[i];
  const Vector6 told = DrivesTakeAt(f, last_utime + 5300);
  EXPECT_LT((next_m - told).cwiseAbs().maxCoeff(), 1e-7);  // where the motion put them
  EXPECT_GT((told - last).cwiseAbs().maxCoeff(), 4e-4);    // not back at the command's own place
  // Still silent past 10 ms: slowing, never back.
  for (std::int64_t k = 6; k <= 13; ++k) f.bridge.Cycle(last_utime + 1000 * k, &state, &fault);
  for (int i = 0; i < kNumLegs; ++i) {
    const double w = command.motor_velocity_rad_s[i], slowed = f.backend.written.motor_velocity_rad_s[i];
    EXPECT_GT(slowed * w, 0.0) << "leg " << i + 1;
    EXPECT_LT(std::abs(slowed), std::abs(w)) << "leg " << i + 1;
  }
  EXPECT_GT((DrivesTakeAt(f, last_utime + 13000) - told).cwiseProduct(next_m - last).minCoeff(), 0.0);
  ASSERT_TRUE(
      f.bridge.HandleCommand(f.Command(1e-4 * 5 + 0.1 * 13.3e-3, last_utime + 13300, 6), last_utime + 13300, &fault))
      << fault.reason;
}

// Commands stop 1 mm below the top of the stroke, rising at 0.1 m/s: the
// motion ridden through would take the legs 2 mm on (1 mm continued, 1 mm
// slowing), and the bridge stops each at its stroke's end instead.
TEST(ActuatorBridge, AMotionRiddenThroughStopsAtTheEndOfTheStroke) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  const double leg_max = f.model.config().limits.leg_max_m;
  auto longest = [&](double dz) {
    const leg_command_t c = f.Command(dz, 0);
    return *std::max_element(std::begin(c.command_length_m), std::end(c.command_length_m));
  };
  int steps = 0;  // 0.1 mm a cycle until the longest leg is within 1 mm of the top
  while (longest(1e-4 * (steps + 1)) < leg_max - 1e-3) ++steps;
  ASSERT_GT(steps, 10);
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, steps);
  ASSERT_FALSE(f.bridge.holding());
  double highest = 0.0;
  for (int k = 0; k < 45; ++k, t += 1000) {  // silent, short of the stale hold
    f.bridge.Cycle(t, &state, &fault);
    highest = std::max(highest, DrivesTakeAt(f, t).maxCoeff());
  }
  EXPECT_LE(highest, leg_max + 1e-12) << "past the stroke by " << (highest - leg_max) * 1e6 << " um";
  EXPECT_NEAR(WrittenLengths(f).maxCoeff(), leg_max, 1e-9);                   // it went on to the end, not held short
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);  // at rest
}

// The whole host paused, the bridge with its planner: the drives went on
// by themselves meanwhile (and the rig emulator bridges such a pause to the
// next command), so until the next command the bridge writes the last one
// as it was: a motion it continued, stamped after the pause, would be taken
// for a command of that instant.
TEST(ActuatorBridge, AfterItsOwnPauseItWritesTheLastCommandAsItWas) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 5);
  const auto command = f.backend.written;
  f.bridge.Cycle(t - 1000 + 16000, &state, &fault);  // 16 ms later
  for (int k = 1; k <= 8; ++k) {
    f.bridge.Cycle(t - 1000 + 16000 + 1000 * k, &state, &fault);
    EXPECT_EQ(f.backend.written.motor_angle_rad, command.motor_angle_rad) << k;
    EXPECT_EQ(f.backend.written.motor_velocity_rad_s, command.motor_velocity_rad_s) << k;
    EXPECT_EQ(f.backend.written.utime, command.utime) << k;
  }
  // The next command is followed, and a silence after it ridden through.
  ASSERT_TRUE(f.bridge.HandleCommand(f.Command(1e-4 * 5 + 0.1 * 25e-3, t + 24000, 6), t + 24000, &fault))
      << fault.reason;
  for (int k = 0; k <= 4; ++k) f.bridge.Cycle(t + 24000 + 1000 * k, &state, &fault);
  EXPECT_EQ(f.backend.written.utime, t + 28000);
}

// Commands stopped and the motion is being ridden through when the bridge
// itself pauses 10 ms: the drives went on along what they were last told
// and stopped on their own watchdog. The bridge repeats that setpoint as it
// was, never the command behind it, and its stale hold holds the drives
// where they stopped (a pulled link did this and the platform rose 3 mm
// back to the command).
TEST(ActuatorBridge, APauseOfItsOwnDuringARideThroughNeverPullsTheDrivesBack) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 5);  // 0.1 m/s up; the last command at t - 1000
  const Vector6 command = WrittenLengths(f);
  for (int k = 0; k < 15; ++k, t += 1000) f.bridge.Cycle(t, &state, &fault);  // riding through
  const DriveSetpoint ridden = f.backend.written;
  const std::int64_t last_cycle = t - 1000;
  const Vector6 ridden_m = WrittenLengths(f);
  ASSERT_GT((ridden_m - command).minCoeff(), 1e-3 * 0.1);  // a millimetre's tenth past the command
  // The drives continue it 4 ms by themselves, then hold (the rig's watchdog).
  std::array<double, 6> stopped{};
  for (int i = 0; i < kNumLegs; ++i) stopped[i] = ridden.motor_angle_rad[i] + ridden.motor_velocity_rad_s[i] * 4e-3;
  f.backend.stopped_at = stopped;
  t = last_cycle + 10000;  // the pause
  const Vector6 up = (ridden_m - command).cwiseSign();
  bool held = false;
  for (; t < last_cycle + 80000; t += 1000) {
    held = f.bridge.Cycle(t, &state, &fault) || held;
    if (f.bridge.holding()) break;
    EXPECT_EQ(f.backend.written.motor_angle_rad, ridden.motor_angle_rad) << "at " << t - last_cycle << " us";
    EXPECT_EQ(f.backend.written.motor_velocity_rad_s, ridden.motor_velocity_rad_s);
    EXPECT_EQ(f.backend.written.utime, ridden.utime);
  }
  ASSERT_TRUE(held) << "no stale hold";
  EXPECT_EQ(f.backend.written.motor_angle_rad, stopped);  // held where they stopped
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
  EXPECT_GT((WrittenLengths(f) - ridden_m).cwiseProduct(up).minCoeff(), 0.0);  // on from the ride, never back
}

// The whole host stood 39 ms mid-motion, the bridge with it: the drives
// stopped on their watchdog 4 ms on while the planner's time ran on, and its
// stream comes back 3.9 mm ahead. Passed on as it came, the servo caught it
// at 0.7 m/s (a multi-host run); the bridge rejoins it from where the drives
// stand at the rejoin speed instead, and follows it again once caught.
TEST(ActuatorBridge, AStreamThatWentOnWithoutTheDrivesIsRejoinedNotStepped) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 5);  // 0.1 m/s up; the last command, dz 0.5 mm, at t - 1000
  const DriveSetpoint last = f.backend.written;
  std::array<double, 6> stood{};
  for (int i = 0; i < kNumLegs; ++i) stood[i] = last.motor_angle_rad[i] + last.motor_velocity_rad_s[i] * 4e-3;
  f.backend.stopped_at = stood;
  f.backend.status.fill(DriveStatus::kHolding);  // as the rig emulator's drives say
  const std::int64_t back = t - 1000 + 39000;
  f.bridge.Cycle(back, &state, &fault);  // its first cycle after the stall reads where they stood
  const double rejoin_step_m = Fixture::Options().rejoin_speed_m_s * 1e-3;
  Vector6 told;  // from where they stood
  for (int i = 0; i < kNumLegs; ++i) told(i) = f.model.LengthFromMotorAngle(i, stood[i]);
  int k = 0;
  double gap_left = 0.0;
  for (; k < 400; ++k) {  // the stream goes on 30 ms more, then holds its last pose
    const double dz = 1e-4 * 5 + 1e-4 * (39 + std::min(k, 30));
    const std::int64_t now = back + 1000 * k + 300;
    const Vector6 command = CommandLengths(f.Command(dz, now, 6 + k));
    if (k == 0) gap_left = (command - told).cwiseAbs().maxCoeff();
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(dz, now, 6 + k), now, &fault)) << k << ": " << fault.reason;
    if (k == 0) {
      EXPECT_TRUE(f.bridge.rejoining());
    }
    f.backend.stopped_at.reset();  // following what they are told from here
    f.backend.status.fill(DriveStatus::kEnabled);
    f.bridge.Cycle(back + 1000 * (k + 1), &state, &fault);
    const Vector6 now_told = WrittenLengths(f);
    // The gap to the stream closes at the rejoin speed (where the stream
    // went during the stall is the gap), never by a step.
    const double gap = (command - now_told).cwiseAbs().maxCoeff();
    EXPECT_LE(gap_left - gap, rejoin_step_m + 1e-9) << "cycle " << k;
    gap_left = gap;
    told = now_told;
    if (!f.bridge.rejoining()) break;
  }
  EXPECT_FALSE(f.bridge.rejoining()) << "never caught the stream";
  EXPECT_FALSE(f.bridge.holding());
  EXPECT_FALSE(f.bridge.latched());
}

// A stream that goes on faster than the rejoin speed after the drives
// stood (a stall mid-motion on a slow controller) is still caught: the legs
// go with it and close the gap at the rejoin speed on top, never beyond the
// legs' speed limit; closing at the rejoin speed alone, they trailed a
// 0.1 m/s motion for as long as it lasted.
TEST(ActuatorBridge, AStreamFasterThanTheRejoinSpeedIsCaughtWhileItMoves) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 5);  // 0.1 m/s up
  std::array<double, 6> stood{};
  for (int i = 0; i < kNumLegs; ++i) stood[i] = f.backend.written.motor_angle_rad[i];
  f.backend.stopped_at = stood;
  f.backend.status.fill(DriveStatus::kHolding);
  const std::int64_t back = t - 1000 + 39000;
  f.bridge.Cycle(back, &state, &fault);
  const double limit_m = f.model.config().limits.leg_speed_max_m_s * 1e-3 + 1e-6;
  Vector6 told = WrittenLengths(f);
  double gap = 0.0, largest_step = 0.0;
  int k = 0;
  for (; k < 2000; ++k) {  // the stream goes on at 0.1 m/s for 2 s
    const double dz = 1e-4 * (5 + 39 + k);
    const std::int64_t now = back + 1000 * k + 300;
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(dz, now, 6 + k), now, &fault)) << k << ": " << fault.reason;
    if (k == 0) {
      EXPECT_TRUE(f.bridge.rejoining());
      gap = (CommandLengths(f.Command(dz, now, 6)) - told).cwiseAbs().maxCoeff();
    }
    f.backend.stopped_at.reset();
    f.backend.status.fill(DriveStatus::kEnabled);
    f.bridge.Cycle(back + 1000 * (k + 1), &state, &fault);
    largest_step = std::max(largest_step, (WrittenLengths(f) - told).cwiseAbs().maxCoeff());
    told = WrittenLengths(f);
    if (!f.bridge.rejoining()) break;
  }
  EXPECT_FALSE(f.bridge.rejoining()) << "still trailing the stream after " << k << " ms";
  EXPECT_LE(k, static_cast<int>(gap / (Fixture::Options().rejoin_speed_m_s * 1e-3)) + 2);
  EXPECT_LE(largest_step, limit_m);
}

// A stream that moves nearly at the legs' speed limit leaves the rejoin
// less than its speed to close with: the legs never step past the limit,
// close what is left, and catch it still.
TEST(ActuatorBridge, ARejoinNeverStepsPastTheLegsLimitBesideAStreamNearIt) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = LatchAtHome(f);
  f.bridge.Rearm();
  // The stream's fastest leg at up to 97% of the legs' limit (its largest
  // rate of length in z along the path).
  const double limit_m = f.model.config().limits.leg_speed_max_m_s * 1e-3;
  double leg_per_z = 0.0;
  for (double z = 0.0; z < 0.12; z += 0.005) {
    leg_per_z = std::max(
        leg_per_z,
        (CommandLengths(f.Command(z + 1e-4, t, 2)) - CommandLengths(f.Command(z, t, 2))).cwiseAbs().maxCoeff() / 1e-4);
  }
  const double dz_per_ms = 0.97 * limit_m / leg_per_z;
  Vector6 told = WrittenLengths(f);
  const double first_gap = (CommandLengths(f.Command(0.005, t, 2)) - told).cwiseAbs().maxCoeff();
  double largest_step = 0.0;
  int k = 0;
  for (; k < 1500 && (k == 0 || f.bridge.rejoining()); ++k, t += 1000) {
    const double dz = 0.005 + dz_per_ms * k;  // 5 mm ahead, running away
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(dz, t, 2 + k), t, &fault)) << k << ": " << fault.reason;
    f.bridge.Cycle(t, &state, &fault);
    largest_step = std::max(largest_step, (WrittenLengths(f) - told).cwiseAbs().maxCoeff());
    told = WrittenLengths(f);
  }
  EXPECT_LE(largest_step, limit_m + 1e-6 + 1e-12);  // the bridge's own slack of 1 µm
  EXPECT_FALSE(f.bridge.rejoining()) << "never caught a stream near the legs' limit";
  // Never closing faster than the rejoin speed.
  EXPECT_GE(k, static_cast<int>(first_gap / (Fixture::Options().rejoin_speed_m_s * 1e-3)) - 1);
}

TEST(ActuatorBridge, WhileRejoiningAJumpInTheStreamIsStillRefused) {
  Fixture f;
  fault_t fault;
  std::int64_t t = LatchAtHome(f);
  f.bridge.Rearm();
  leg_state_t state;
  ASSERT_TRUE(f.bridge.HandleCommand(f.Command(0.05, t, 2), t, &fault));
  f.bridge.Cycle(t, &state, &fault);
  const Vector6 after_first = WrittenLengths(f);
  t += 1000;
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(0.10, t, 3), t, &fault));  // 50 mm in 1 ms
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kJump));
  EXPECT_NE(fault.reason.find("previous command"), std::string::npos) << fault.reason;
  f.bridge.Cycle(t, &state, &fault);
  EXPECT_EQ(WrittenLengths(f), after_first);
  EXPECT_TRUE(f.bridge.rejoining());
}

// Drives that stop answering mid-motion: the bridge holds where it was told
// to be, at rest, refuses the stream, and moves again only when re-armed
// after the drives answer.
TEST(ActuatorBridge, DrivesThatStopAnsweringLatchAHoldUntilReArmed) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 20);  // moving up at 0.1 m/s
  int seq = 21;
  f.backend.answering = false;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kBackend));
  EXPECT_NE(fault.reason.find("until re-armed"), std::string::npos) << fault.reason;
  EXPECT_TRUE(f.bridge.holding());
  EXPECT_TRUE(f.bridge.latched());
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
  const Vector6 held = WrittenLengths(f);
  t += 1000;
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(1e-4 * seq, t, seq), t, &fault));
  EXPECT_NE(fault.reason.find("holding after a drive outage"), std::string::npos) << fault.reason;
  ++seq;
  f.bridge.Rearm();  // the operator tries while the drives are still silent
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(1e-4 * seq, t, seq), t, &fault));
  EXPECT_NE(fault.reason.find("do not answer"), std::string::npos) << fault.reason;
  EXPECT_EQ(WrittenLengths(f), held);
  ++seq;
  f.backend.answering = true;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_EQ(fault.severity, fault_t::SEVERITY_INFO);
  EXPECT_NE(fault.reason.find("answers again"), std::string::npos) << fault.reason;
  t += 1000;
  ASSERT_TRUE(f.bridge.HandleCommand(f.Command(1e-4 * seq, t, seq), t, &fault)) << fault.reason;
}

// An outage whose reason changes (the link refused, then the drives back in
// fault) tells the operator each reason once, the latest, and no sooner than
// the fault throttle lets it through (100 ms after the last).
TEST(ActuatorBridge, DrivesStillLostReportEachNewReasonOnce) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 1e-4, 20);
  const std::string refused = "modbus-tcp 127.0.0.1:1502: cannot connect: Connection refused";
  const std::string in_fault = "drive 3 in fault (error code 8130h)";
  f.backend.answering = false;
  f.backend.detail = refused;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_NE(fault.reason.find("Connection refused"), std::string::npos) << fault.reason;
  const std::int64_t lost_utime = t;
  // A new reason 5 ms later waits for the throttle's 100 ms, then goes out.
  std::int64_t reported_utime = -1;
  for (int k = 0; k < 200 && reported_utime < 0; ++k) {
    t += 1000;
    if (t - lost_utime == 5000) f.backend.detail = in_fault;
    if (f.bridge.Cycle(t, &state, &fault)) reported_utime = t;
  }
  EXPECT_EQ(reported_utime - lost_utime, 100000);
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kBackend));
  EXPECT_GE(fault.severity, fault_t::SEVERITY_WARNING);
  EXPECT_NE(fault.reason.find(in_fault), std::string::npos) << fault.reason;
  // Reasons that come back (a reconnect refused, the drives read again in
  // fault, …) are not reported again in this outage.
  for (int k = 0; k < 1000; ++k) {
    t += 1000;
    f.backend.detail = (k / 50) % 2 == 0 ? refused : in_fault;
    EXPECT_FALSE(f.bridge.Cycle(t, &state, &fault)) << fault.reason;
  }
  EXPECT_TRUE(f.bridge.latched());
  // Back, and lost again: a new outage, its reason reported anew.
  f.backend.answering = true;
  f.backend.detail.clear();
  t += 1000;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_NE(fault.reason.find("answers again"), std::string::npos) << fault.reason;
  f.backend.answering = false;
  f.backend.detail = in_fault;
  t += 1000;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_NE(fault.reason.find("8130h"), std::string::npos) << fault.reason;
}

// A bridge restarted while the stream is elsewhere (its predecessor was
// killed mid-motion) starts holding where the drives are, refuses the
// stream as a jump, and rejoins it when re-armed.
TEST(ActuatorBridge, ARestartedBridgeRefusesAStreamElsewhereUntilReArmed) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  for (int k = 0; k < 10; ++k, t += 1000) f.bridge.Cycle(t, &state, &fault);
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(0.01, t, 100), t, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kJump));
  f.bridge.Rearm();
  int k = 0;
  for (; k < 2000 && (k == 0 || f.bridge.rejoining()); ++k, t += 1000) {
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(0.01, t, 101 + k), t, &fault)) << fault.reason;
  }
  EXPECT_FALSE(f.bridge.rejoining());
  EXPECT_GT(k, 300);  // 10 mm at 0.02 m/s: about half a second, not a jump
}

// The bridge itself frozen (SIGSTOP, a long deschedule) mid-motion: no cycle
// ran to notice the silence, and the first command after it is fresh but
// far from the held target. It must hold and latch, not jump there, and
// hold the drives where their watchdog stopped them (found under ASan, where
// the thawed bridge handled a command before its first cycle).
TEST(ActuatorBridge, AFreshCommandAfterTheBridgesOwnFreezeIsRefusedAndLatches) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 3e-5, 20);  // moving up at 0.03 m/s
  const std::array<double, 6> past = StopDrivesAhead(f);
  t += 500000;  // frozen for 0.5 s; the stream went on 15 mm
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(3e-5 * 520, t, 520), t, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kLatched));
  EXPECT_NE(fault.reason.find("until re-armed"), std::string::npos) << fault.reason;
  EXPECT_TRUE(f.bridge.latched());
  EXPECT_FALSE(f.bridge.Cycle(t, &state, &fault)) << "reported once, by the refusal: " << fault.reason;
  EXPECT_EQ(f.backend.written.motor_angle_rad, past) << "held where the drives stopped, not pulled back";
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
}

// The same freeze shorter than the stale limit as seen by the cycle (it ran
// 45 ms before the command came 51 ms after the last one): the cycle's own
// starvation check cannot see it, the command's refusal must leave the
// hold where the drives are to the next cycle's read. Re-armed in between
// (an operator's EDSP_ARM queued with the commands), the stream must wait
// for that read, not rejoin from the last command.
TEST(ActuatorBridge, AfterAFreezeTheHoldWaitsForTheNextReadEvenWhenReArmedFirst) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 3e-5, 20);
  const std::int64_t last_command = t - 1000;
  f.bridge.Cycle(last_command + 45000, &state, &fault);  // the last cycle before the freeze
  ASSERT_FALSE(f.bridge.holding());
  const std::array<double, 6> past = StopDrivesAhead(f);
  t = last_command + 51000;
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(3e-5 * 70, t, 70), t, &fault));
  EXPECT_TRUE(f.bridge.latched());
  EXPECT_TRUE(f.bridge.Rearm());
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(3e-5 * 71, t, 71), t, &fault));
  EXPECT_NE(fault.reason.find("not read yet"), std::string::npos) << fault.reason;
  f.bridge.Cycle(t, &state, &fault);
  EXPECT_EQ(f.backend.written.motor_angle_rad, past) << "held where the drives stopped, not pulled back";
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
  // Read: the stream rejoins from there.
  t += 1000;
  ASSERT_TRUE(f.bridge.HandleCommand(f.Command(3e-5 * 72, t, 72), t, &fault)) << fault.reason;
  f.bridge.Cycle(t, &state, &fault);
  EXPECT_TRUE(f.bridge.rejoining());
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_LE(std::abs(f.backend.written.motor_angle_rad[i] - past[i]),
              f.model.MotorAngleFromLength(i, 1.5 + Fixture::Options().rejoin_speed_m_s * 1e-3) -
                  f.model.MotorAngleFromLength(i, 1.5) + 1e-9)
        << "leg " << i + 1 << ": one rejoin step from where the drives stopped";
  }
}

// Frozen while the drives went on interpolating for a few cycles and then
// stopped on their watchdog: when the bridge runs again it holds them where
// they stopped, not back at its last command (which would move them).
TEST(ActuatorBridge, AfterItsOwnFreezeTheBridgeHoldsTheDrivesWhereTheyStopped) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  MoveUp(f, &t, 3e-5, 20);
  const std::array<double, 6> past = StopDrivesAhead(f);
  t += 500000;
  ASSERT_TRUE(f.bridge.Cycle(t, &state, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kLatched));
  EXPECT_TRUE(f.bridge.latched());
  EXPECT_EQ(f.backend.written.motor_angle_rad, past);
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace edsp
