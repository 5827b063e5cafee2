// The bridge forwards only what it can validate and holds on stale input;
// tested against a fake backend that records what the drives were told.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/kinematics/config.h"

namespace edsp {
namespace {

class RecordingBackend final : public DriveBackend {
 public:
  bool Configure(const PlatformConfig&, std::string*) override { return true; }
  bool Activate(std::string*) override { return true; }
  void Deactivate() override {}
  bool Read(std::int64_t, DriveFeedback* feedback) override {
    feedback->motor_angle_rad = written.motor_angle_rad;  // a perfect drive
    feedback->status.fill(DriveStatus::kEnabled);
    return true;
  }
  bool Write(std::int64_t, const DriveSetpoint& setpoint) override {
    written = setpoint;
    ++writes;
    return true;
  }
  BackendState state() const override { return BackendState::kActive; }
  DriveSetpoint written;
  int writes = 0;
};

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

TEST(ActuatorBridge, StartUpHoldIsNotLatched) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  for (int k = 0; k < 100; ++k) f.bridge.Cycle(kStart - 100000 + k * 1000, &state, &fault);
  EXPECT_TRUE(f.bridge.holding());
  EXPECT_FALSE(f.bridge.latched());
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(0.0, kStart), kStart, &fault)) << fault.reason;
}

TEST(ActuatorBridge, ValidCommandsReachTheDrivesAsMotorAngles) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  for (int k = 1; k <= 100; ++k, t += 1000) {  // 0.1 mm per ms = 0.1 m/s
    const leg_command_t c = f.Command(1e-4 * k, t, k);
    ASSERT_TRUE(f.bridge.HandleCommand(c, t, &fault)) << fault.reason;
    // At the drives on arrival, before the cycle: latency is the transport's.
    EXPECT_NEAR(f.backend.written.motor_angle_rad[2], f.model.MotorAngleFromLength(2, c.command_length_m[2]), 1e-12);
    EXPECT_FALSE(f.bridge.Cycle(t, &state, &fault));
  }
  const leg_command_t last = f.Command(1e-2, t - 1000, 100);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_NEAR(f.backend.written.motor_angle_rad[i],
                f.model.MotorAngleFromLength(i, last.command_length_m[i]), 1e-9);
    EXPECT_NEAR(state.encoder_length_m[i], last.command_length_m[i], 1e-12);
    EXPECT_GT(f.backend.written.motor_velocity_rad_s[i], 0.0);  // feed-forward while rising
    EXPECT_EQ(state.drive_status[i], leg_state_t::DRIVE_ENABLED);
  }
  EXPECT_EQ(state.command_seq, 100);
  EXPECT_FALSE(f.bridge.holding());
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

TEST(ActuatorBridge, HoldsTheLastValidPositionWithin50msOfSilence) {
  Fixture f;
  fault_t fault;
  leg_state_t state;
  std::int64_t t = kStart;
  for (int k = 1; k <= 20; ++k, t += 1000) {
    ASSERT_TRUE(f.bridge.HandleCommand(f.Command(1e-4 * k, t, k), t, &fault));
    f.bridge.Cycle(t, &state, &fault);
  }
  const auto held = f.backend.written.motor_angle_rad;
  int faults = 0;
  std::int64_t hold_at = -1;
  for (int k = 0; k < 200; ++k, t += 1000) {  // commands stop
    if (f.bridge.Cycle(t, &state, &fault)) {
      ++faults;
      EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kStale));
      if (hold_at < 0) hold_at = t;
    }
    EXPECT_EQ(f.backend.written.motor_angle_rad, held);  // never moves on its own
  }
  EXPECT_EQ(faults, 1);  // reported once, not every cycle
  EXPECT_LE(hold_at - (kStart + 19000), 51000);
  EXPECT_TRUE(f.bridge.holding());
  for (double v : f.backend.written.motor_velocity_rad_s) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(state.drive_status[0], leg_state_t::DRIVE_HOLDING);
  // Latched: even a command continuing exactly from the hold is refused.
  EXPECT_TRUE(f.bridge.latched());
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(2e-3 + 1e-5, t, 21), t, &fault));
  EXPECT_NE(fault.reason.find("re-arm required"), std::string::npos) << fault.reason;
  f.bridge.Rearm();
  // Re-armed: a command far from the hold (the planner moved on) is a jump ...
  EXPECT_FALSE(f.bridge.HandleCommand(f.Command(0.2, t, 22), t, &fault));
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kJump));
  // ... one continuing from the hold is accepted.
  EXPECT_TRUE(f.bridge.HandleCommand(f.Command(2e-3 + 1e-5, t, 23), t, &fault)) << fault.reason;
  EXPECT_FALSE(f.bridge.holding());
}

}  // namespace
}  // namespace edsp
