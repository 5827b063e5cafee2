// A controller that stalls while the drives do not (a planner tick missed
// on a loaded host): the actuator bridge and the rig emulator's drive cycle
// composed as the live group runs them, on a deterministic clock: the
// planner's tick, the bridge's cycle 0.4 ms after it, the drives' 0.1 ms
// after that. The rig is config/huang2021-rig-effects.toml's: a
// torque-limited servo, legs compliant under 800 kg. The platform through
// the stall is compared with the same run without it.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/rig/virtual_rig.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

constexpr std::int64_t kStart = 1700000000000000;

// The drives as the bridge sees them: it writes into the rig's next cycle
// and reads its last feedback.
class RigDrives final : public DriveBackend {
 public:
  explicit RigDrives(VirtualRig* rig) : rig_(rig) {}
  bool Configure(const PlatformConfig&, std::string*) override { return true; }
  bool Activate(std::string*) override { return true; }
  void Deactivate() override {}
  bool Read(std::int64_t, DriveFeedback* feedback) override {
    *feedback = rig_->Feedback();
    return true;
  }
  bool Write(std::int64_t, const DriveSetpoint& setpoint) override {
    written = setpoint;
    return true;
  }
  bool Reset(std::string*) override { return true; }
  BackendState state() const override { return BackendState::kActive; }
  std::string Detail() const override { return {}; }
  DriveSetpoint written;

 private:
  VirtualRig* rig_;
};

RigParameters RigWithEffects() {
  const std::string path = SourcePath("config/huang2021-rig-effects.toml");
  RigParameters p = IdealRig(LoadConfigFile(path));
  p.effects = LoadRigEffects(path);
  p.tracker.noise_sigma_m = 0.0;
  return p;
}

// Up along z: 2 m/s² from rest to 0.2 m/s, then cruising.
double HeightAt(double t_s) { return t_s < 0.1 ? t_s * t_s : 0.01 + 0.2 * (t_s - 0.1); }

// Ticks [from, to) of the 1 kHz grid.
struct Ticks {
  int from = 0, to = 0;
  bool Contain(int k) const { return k >= from && k < to; }
};

// The platform's true position each cycle over 300 ms; the planner's ticks
// in `stalled` never come, and in `paused` nothing runs (the whole host
// descheduled: planner, bridge and emulator).
std::vector<Vector3> RunStalledStack(Ticks stalled, Ticks paused = {}) {
  const PlatformModel model(Huang2021Config());
  VirtualRig rig(RigWithEffects());
  RigDrives drives(&rig);
  BridgeOptions options;
  options.session_id = 1;
  ActuatorBridge bridge(model, &drives, options);
  RigCycle cycle(&rig, 1e-3, 2.5e-3);
  std::vector<Vector3> path;
  fault_t fault;
  leg_state_t state;
  std::int64_t seq = 0;
  for (int k = 0; k < 300; ++k) {
    const std::int64_t tick = kStart + 1000 * k;
    if (paused.Contain(k)) continue;
    if (!stalled.Contain(k)) {
      Pose pose = model.home_pose();
      pose.p_BoMo_B.z() += HeightAt(1e-3 * k);
      const Vector6 lengths = model.CompensatedLengths(pose, PrMode::kSigned);
      leg_command_t c{};
      c.utime = c.setpoint_utime = tick;
      c.seq = ++seq;
      c.session_id = 1;
      for (int i = 0; i < kNumLegs; ++i) c.command_length_m[i] = lengths(i);
      EXPECT_TRUE(bridge.HandleCommand(c, tick + 300, &fault)) << fault.reason;
    }
    bridge.Cycle(tick + 400, &state, &fault);
    for (const RigCycleReport& r : cycle.Wake(tick + 500, {DriveCommand{drives.written, true}})) {
      EXPECT_FALSE(r.physics_failed);
      path.push_back(Vector3(r.truth.pose[0], r.truth.pose[1], r.truth.pose[2]));
    }
  }
  return path;
}

double FurthestApart(const std::vector<Vector3>& a, const std::vector<Vector3>& b) {
  EXPECT_EQ(a.size(), b.size());
  double furthest = 0.0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) furthest = std::max(furthest, (a[k] - b[k]).norm());
  return furthest;
}

// 5 ms without a setpoint at 0.2 m/s, the stall that cost a live
// calibration its target: the drives are told the last command's motion
// and the platform stays on its path. Holding the last command's position
// instead pulls the drives 0.5 mm back and the torque-limited servo takes
// the platform 1.1 mm off its path.
TEST(ControllerStall, AFiveMillisecondStallOfThePlannerLeavesThePlatformOnItsPath) {
  const std::vector<Vector3> on_time = RunStalledStack({});
  ASSERT_GT(on_time.back().z() - on_time.front().z(), 0.04);  // it moved 4 cm
  const double furthest = FurthestApart(RunStalledStack({150, 155}), on_time);
  EXPECT_LT(furthest, 2e-6);
  std::printf("STALL_ROW | 5 ms planner stall at 0.2 m/s | furthest from the run without it %.1f um\n", furthest * 1e6);
}

// A longer stall (20 ms): past 10 ms the drives slow at the legs' 5 m/s²,
// and the stream comes back 0.25 mm ahead of them, which the servo then
// catches up (under 800 kg, the legs' compliance adds to that); back on
// the path after it. Holding the last command's position: 5.4 mm off.
TEST(ControllerStall, ATwentyMillisecondStallSlowsThePlatformAndCatchesUp) {
  const std::vector<Vector3> on_time = RunStalledStack({}), stalled = RunStalledStack({150, 170});
  const double furthest = FurthestApart(stalled, on_time);
  EXPECT_LT(furthest, 1e-3);
  EXPECT_LT((stalled.back() - on_time.back()).norm(), 10e-6) << "not back on its path";
  std::printf("STALL_ROW | 20 ms planner stall at 0.2 m/s | furthest %.1f um, at the end %.1f um\n", furthest * 1e6,
              (stalled.back() - on_time.back()).norm() * 1e6);
}

// The whole host paused for 16 ms (the bridge with its planner and the
// emulator): the bridge writes its last command as it was, and the
// emulator, catching up, bridges the pause to the next command, so the
// platform runs on as if nothing had paused: within 10 µm (the on-time rig
// continues each command without the parabola's curvature). Also when the
// planner fell silent 3 ms before the pause and came back a tick after the
// bridge: a motion the bridge had continued and stamped after the pause
// would have been taken for a command of that instant (7 mm off, live).
TEST(ControllerStall, APauseOfTheWholeHostIsBridgedWhateverStalledFirst) {
  const std::vector<Vector3> on_time = RunStalledStack({});
  const double host = FurthestApart(RunStalledStack({}, {150, 166}), on_time);
  const double planner_first = FurthestApart(RunStalledStack({147, 150}, {150, 166}), on_time);
  const double planner_last = FurthestApart(RunStalledStack({147, 167}, {150, 166}), on_time);
  EXPECT_LT(host, 10e-6);
  EXPECT_LT(planner_first, 10e-6);
  EXPECT_LT(planner_last, 10e-6);
  std::printf(
      "STALL_ROW | 16 ms pause of the whole host | furthest %.1f um; the planner silent 3 ms before: %.1f um, and a "
      "tick after: %.1f um\n",
      host * 1e6, planner_first * 1e6, planner_last * 1e6);
}

}  // namespace
}  // namespace edsp
