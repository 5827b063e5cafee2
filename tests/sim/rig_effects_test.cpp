// The rig's physical effects through the whole in-process stack (planner →
// kinematics with signed compensation → bridge → virtual rig, tracker noise
// off). For each effect: the point-A error at every dwell against a hand
// calculation, independent of the rig's forward kinematics: the small-error
// linearisation ΔA = ∂A/∂q · J⁻¹ · Δ(encoder lengths), with both Jacobians by
// finite differences of the models; within 10%. And each effect's signature:
// constant for offsets, ∝ stroke for lead error, flipping with direction for
// backlash, no hysteresis for joint positions. All off: the nominal model.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/sim/stack_simulation.h"

namespace edsp {
namespace {

// No effect at all, the drive ideal too: every stop exactly on target.
RigEffects NoEffects() {
  RigEffects none;
  none.servo_lag.enabled = false;
  return none;
}

struct DwellEnd {
  std::string segment;
  Vector6 target;
  Vector3 error;    // tracker A − target A
  Vector6 command;  // encoder lengths commanded
  Vector6 travel;   // each leg's last direction of travel into the dwell: +1, −1 (0: none yet)
};

std::vector<DwellEnd> RunStack(const std::string& motion, const RigEffects& effects, int stops = 3) {
  const PlatformConfig nominal = Huang2021Config();
  auto trajectory = std::make_unique<TrajectorySequence>();
  PaperMotionOptions options;
  options.stops = stops;
  options.dwell_s = 0.3;
  options.max_speed_m_s = 0.25;
  options.max_speed_rad_s = 0.4;
  AppendPaperMotion(motion, PlatformModel(nominal).home_pose().ToVector(), options, trajectory.get());
  StackOptions stack;
  stack.pr_mode = PrMode::kSigned;
  RigParameters rig = IdealRig(nominal);
  rig.effects = effects;
  stack.rig = rig;
  StackSimulation sim(nominal, std::move(trajectory), stack);
  const PlatformModel& model = sim.nominal_model();
  std::vector<DwellEnd> ends;
  StackSample previous;
  bool have_previous = false;
  Vector6 travel = Vector6::Zero(), last_command = Vector6::Zero();
  while (!sim.Finished()) {
    const StackSample s = sim.Step();
    EXPECT_TRUE(s.command_valid);
    Vector6 command;
    for (int i = 0; i < 6; ++i) command(i) = s.command.command_length_m[i];
    for (int i = 0; i < 6; ++i) {
      const double step = command(i) - last_command(i);
      if (std::abs(step) > 1e-9) travel(i) = step > 0 ? 1.0 : -1.0;
    }
    last_command = command;
    if (have_previous && s.setpoint.segment != previous.setpoint.segment &&
        previous.setpoint.phase == pose_setpoint_t::PHASE_DWELL) {
      DwellEnd d;
      d.segment = previous.setpoint.trajectory;
      for (int k = 0; k < 6; ++k) d.target(k) = previous.setpoint.pose[k];
      for (int i = 0; i < 6; ++i) d.command(i) = previous.command.command_length_m[i];
      const Vector3 measured(previous.tracker.point_m[0], previous.tracker.point_m[1], previous.tracker.point_m[2]);
      d.error = measured - model.ObservationPoint(Pose::FromVector(d.target));
      d.travel = travel;
      ends.push_back(d);
    }
    previous = s;
    have_previous = true;
  }
  // Back home, the planner holds: that is a last stop, reached downwards or
  // upwards depending on the motion.
  StackSample held;
  for (int k = 0; k < 300; ++k) held = sim.Step();
  DwellEnd end;
  end.segment = motion + "/end";
  for (int k = 0; k < 6; ++k) end.target(k) = held.setpoint.pose[k];
  for (int i = 0; i < 6; ++i) end.command(i) = held.command.command_length_m[i];
  end.error = Vector3(held.tracker.point_m[0], held.tracker.point_m[1], held.tracker.point_m[2]) -
              model.ObservationPoint(Pose::FromVector(end.target));
  end.travel = travel;
  ends.push_back(end);
  EXPECT_TRUE(sim.faults().empty());
  return ends;
}

// ΔA for encoder-length errors `delta` at pose q on a rig whose encoder-length
// function is `rig` (nominal unless its geometry or PR differ).
Vector3 Predicted(const PlatformModel& nominal, const PlatformModel& rig, const Vector6& q, const Vector6& delta) {
  const double h = 1e-6;
  Matrix6 J;
  Eigen::Matrix<double, 3, 6> Ja;
  for (int k = 0; k < 6; ++k) {
    Vector6 up = q, down = q;
    up(k) += h;
    down(k) -= h;
    J.col(k) = (rig.EncoderLengths(Pose::FromVector(up)) - rig.EncoderLengths(Pose::FromVector(down))) / (2 * h);
    Ja.col(k) =
        (nominal.ObservationPoint(Pose::FromVector(up)) - nominal.ObservationPoint(Pose::FromVector(down))) / (2 * h);
  }
  const Vector6 mismatch = nominal.EncoderLengths(Pose::FromVector(q)) - rig.EncoderLengths(Pose::FromVector(q));
  return Ja * J.lu().solve(delta + mismatch);
}

void ExpectWithin10Percent(const Vector3& measured, const Vector3& predicted, const std::string& where) {
  EXPECT_LE((measured - predicted).norm(), 0.1 * predicted.norm() + 1e-8)
      << where << ": measured " << measured.transpose() * 1e6 << " µm, hand calculation " << predicted.transpose() * 1e6
      << " µm";
}

const PlatformModel& Nominal() {
  static const PlatformModel model(Huang2021Config());
  return model;
}

TEST(RigEffects, AllOffTheRigIsTheNominalModel) {
  EXPECT_FALSE(NoEffects().any());
  for (const char* motion : {"Lz", "Rz"}) {
    for (const DwellEnd& d : RunStack(motion, NoEffects())) EXPECT_LT(d.error.norm(), 1e-9) << d.segment;
  }
}

TEST(RigEffects, LegOffsetIsAConstantLegErrorMappedThroughTheKinematics) {
  RigEffects e = NoEffects();  // this effect alone
  e.leg_offset.enabled = true;
  e.leg_offset.offset_m = {100e-6, -50e-6, 80e-6, -120e-6, 60e-6, -30e-6};
  const Vector6 delta = Eigen::Map<const Vector6>(e.leg_offset.offset_m.data());
  double largest = 0.0;
  for (const DwellEnd& d : RunStack("Lz", e)) {
    ExpectWithin10Percent(d.error, Predicted(Nominal(), Nominal(), d.target, delta), d.segment);
    largest = std::max(largest, d.error.norm());
  }
  EXPECT_GT(largest, 50e-6);  // tens to hundreds of µm at A
}

TEST(RigEffects, LeadErrorGrowsWithStroke) {
  RigEffects e = NoEffects();  // this effect alone
  e.lead_error.enabled = true;
  e.lead_error.epsilon.fill(300e-6);
  const Vector6 zero = Nominal().EncoderLengths(Nominal().home_pose());
  const std::vector<DwellEnd> ends = RunStack("Lz", e, 5);
  for (const DwellEnd& d : ends) {
    const Vector6 delta = 300e-6 * (d.command - zero);
    ExpectWithin10Percent(d.error, Predicted(Nominal(), Nominal(), d.target, delta), d.segment);
  }
  // Stops at −0.5, −0.25, 0, +0.25, +0.5 m: zero at home, growing with the
  // stroke, about twice at twice the stroke (exactly so in leg space; the
  // map to A bends it a little, which the hand calculation above includes).
  ASSERT_EQ(ends.size(), 6u);  // 5 stops + home
  EXPECT_LT(ends[2].error.norm(), 1e-8);
  for (int k : {0, 4}) {
    const double ratio =
        ends[static_cast<std::size_t>(k)].error.norm() / ends[static_cast<std::size_t>(k == 0 ? 1 : 3)].error.norm();
    EXPECT_GT(ratio, 1.7) << k;
    EXPECT_LT(ratio, 2.3) << k;
  }
  EXPECT_GT(ends[4].error.norm(), 20e-6);
}

TEST(RigEffects, PeriodicLeadErrorFollowsTheScrewAngle) {
  RigEffects e = NoEffects();  // this effect alone
  e.periodic_lead_error.enabled = true;
  e.periodic_lead_error.amplitude_m.fill(5e-6);
  e.periodic_lead_error.phase_rad = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0};
  const Vector6 zero = Nominal().EncoderLengths(Nominal().home_pose());
  const double lead = Nominal().config().drive.lead_m;
  for (const DwellEnd& d : RunStack("Lz", e, 5)) {
    Vector6 delta;
    for (int i = 0; i < 6; ++i) {
      const double screw = 2 * M_PI * (d.command(i) - zero(i)) / lead;
      const double phase = e.periodic_lead_error.phase_rad[static_cast<std::size_t>(i)];
      delta(i) = 5e-6 * (std::sin(screw + phase) - std::sin(phase));
    }
    ExpectWithin10Percent(d.error, Predicted(Nominal(), Nominal(), d.target, delta), d.segment);
  }
}

TEST(RigEffects, BacklashFlipsWithTheDirectionOfTravel) {
  RigEffects e = NoEffects();  // this effect alone
  e.backlash.enabled = true;
  e.backlash.backlash_m.fill(30e-6);
  const std::vector<DwellEnd> ends = RunStack("Lz", e, 3);  // −0.5 (down), 0 (up), +0.5 (up), home (down)
  ASSERT_EQ(ends.size(), 4u);
  for (const DwellEnd& d : ends) {
    Vector6 delta;  // a retracting leg is longer than its encoder says by the whole backlash
    for (int i = 0; i < 6; ++i) delta(i) = d.travel(i) < 0 ? 30e-6 : 0.0;
    ExpectWithin10Percent(d.error, Predicted(Nominal(), Nominal(), d.target, delta), d.segment);
  }
  // Home reached upwards (the 0 stop) and downwards (the end): two errors.
  EXPECT_LT(ends[1].error.norm(), 1e-8);
  EXPECT_GT(ends[3].error.norm(), 20e-6);
  EXPECT_GT(ends[0].error.norm(), 20e-6);
}

TEST(RigEffects, PassiveRotationWithTheWrongSignDoublesThePrError) {
  RigEffects e = NoEffects();  // this effect alone
  e.passive_rotation.enabled = true;
  e.passive_rotation.pr_sign = -1;  // the model says +1
  PlatformConfig rig_config = Huang2021Config();
  rig_config.drive.pr_sign = -1;
  const PlatformModel rig(rig_config);
  double largest = 0.0;
  for (const DwellEnd& d : RunStack("Rz", e)) {
    ExpectWithin10Percent(d.error, Predicted(Nominal(), rig, d.target, Vector6::Zero()), d.segment);
    largest = std::max(largest, d.error.norm());
  }
  EXPECT_GT(largest, 2.5e-3);  // about twice the 1.41 mm of no compensation at Rz 30°
}

TEST(RigEffects, JointPositionErrorsArePoseDependentWithoutHysteresis) {
  RigEffects e = NoEffects();  // this effect alone
  e.joint_position.enabled = true;
  for (int i = 0; i < 6; ++i) {
    e.joint_position.base_m.col(i) = Vector3(std::sin(i), std::cos(2 * i), 0.5 * std::sin(3 * i)) * 200e-6;
    e.joint_position.platform_m.col(i) = Vector3(std::cos(i), std::sin(2 * i), 0.3) * 150e-6;
  }
  const PlatformModel rig(TrueConfig(Huang2021Config(), e));
  const std::vector<DwellEnd> ends = RunStack("Rz", e, 3);
  for (const DwellEnd& d : ends) {
    ExpectWithin10Percent(d.error, Predicted(Nominal(), rig, d.target, Vector6::Zero()), d.segment);
  }
  ASSERT_EQ(ends.size(), 4u);  // −30°, 0 (from below), +30°, home (from above)
  EXPECT_GT(ends[1].error.norm(), 50e-6);
  EXPECT_LT((ends[1].error - ends[3].error).norm(), 1e-9);   // same pose, same error
  EXPECT_GT((ends[0].error - ends[1].error).norm(), 10e-6);  // but it depends on the pose
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

struct LagStats {
  double max_error_m = 0.0;       // |commanded − encoder| leg length in motion
  double max_predicted_m = 0.0;   // from the leg acceleration, see below
  double max_rest_error_m = 0.0;  // at the end of each dwell
};

LagStats RunServoLag(double speed_m_s, double bandwidth_hz) {
  const PlatformConfig nominal = Huang2021Config();
  auto trajectory = std::make_unique<TrajectorySequence>();
  PaperMotionOptions options;
  options.stops = 2;
  options.dwell_s = 0.3;
  options.max_speed_m_s = speed_m_s;
  AppendPaperMotion("Lz", PlatformModel(nominal).home_pose().ToVector(), options, trajectory.get());
  StackOptions stack;
  RigParameters rig = IdealRig(nominal);
  rig.effects.servo_lag.enabled = true;
  rig.effects.servo_lag.bandwidth_hz = bandwidth_hz;
  stack.rig = rig;
  StackSimulation sim(nominal, std::move(trajectory), stack);
  const double wn = 2 * M_PI * bandwidth_hz;
  LagStats stats;
  std::vector<Vector6> commands;
  StackSample previous;
  while (!sim.Finished()) {
    const StackSample s = sim.Step();
    Vector6 cmd, enc;
    for (int i = 0; i < 6; ++i) {
      cmd(i) = s.command.command_length_m[i];
      enc(i) = s.legs.encoder_length_m[i];
    }
    commands.push_back(cmd);
    stats.max_error_m = std::max(stats.max_error_m, (cmd - enc).cwiseAbs().maxCoeff());
    if (commands.size() >= 3) {
      const std::size_t n = commands.size();
      const Vector6 accel = (commands[n - 1] - 2 * commands[n - 2] + commands[n - 3]) / 1e-6;
      // Steady-state error of the critically damped loop under acceleration a,
      // a/ωn², plus what the bridge's feed-forward adds: its velocity is a
      // 1 ms difference, half a cycle (T/2) late, which the damping term
      // (kd/kp = 2/ωn) turns into a·T/ωn; and the drive's 1 ms extrapolation
      // between commands falls a·T² short.
      const double a = accel.cwiseAbs().maxCoeff(), T = 1e-3;
      stats.max_predicted_m = std::max(stats.max_predicted_m, a / (wn * wn) * (1 + wn * T) + a * T * T);
    }
    if (commands.size() > 1 && s.setpoint.segment != previous.setpoint.segment &&
        previous.setpoint.phase == pose_setpoint_t::PHASE_DWELL) {
      for (int i = 0; i < 6; ++i) {
        stats.max_rest_error_m = std::max(
            stats.max_rest_error_m, std::abs(previous.command.command_length_m[i] - previous.legs.encoder_length_m[i]));
      }
    }
    previous = s;
  }
  EXPECT_TRUE(sim.faults().empty());
  return stats;
}

// A critically damped loop with velocity and friction feed-forward tracks a
// constant speed exactly; what is left follows the acceleration.
TEST(RigEffects, ServoLagVanishesAtRestAndGrowsWithTheMotion) {
  const LagStats slow = RunServoLag(0.125, 40.0);
  const LagStats fast = RunServoLag(0.25, 40.0);
  EXPECT_LT(fast.max_rest_error_m, 1e-9);
  EXPECT_NEAR(fast.max_error_m, fast.max_predicted_m, 0.1 * fast.max_predicted_m);
  EXPECT_NEAR(slow.max_error_m, slow.max_predicted_m, 0.1 * slow.max_predicted_m);
  EXPECT_NEAR(fast.max_error_m / slow.max_error_m, 4.0, 0.4);  // quintic: acceleration ∝ speed²
  EXPECT_GT(fast.max_error_m, 1e-6);
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

// Each leg's axis at a pose: its vertical component (all six alike for the
// symmetric platform in vertical-only poses).
double LegAxisZ(const PlatformModel& model, const Vector6& q) {
  const LegSolution legs = model.Solve(Pose::FromVector(q));
  return legs.u_B(2, 0);
}

// At rest, by symmetry, each of the six legs carries m·g / (6·u_z): they
// shorten by that over k and the platform sinks by it over u_z. In motion the
// vertical acceleration adds to g.
TEST(RigEffects, ComplianceSagsByTheLegForcesItCarries) {
  const double k = 2e7, m = 800.0;
  RigEffects e = NoEffects();  // this effect alone
  e.compliance.enabled = true;
  e.compliance.stiffness_N_m.fill(k);
  e.compliance.mass_kg = m;
  const std::vector<DwellEnd> ends = RunStack("Lz", e, 3);
  for (const DwellEnd& d : ends) {
    const double uz = LegAxisZ(Nominal(), d.target);
    for (int i = 1; i < 6; ++i) EXPECT_NEAR(Nominal().Solve(Pose::FromVector(d.target)).u_B(2, i), uz, 1e-12);
    const Vector3 predicted(0.0, 0.0, -m * 9.81 / (6 * k * uz * uz));
    ExpectWithin10Percent(d.error, predicted, d.segment);
  }
  // Lower poses have flatter legs: more force, more sag.
  EXPECT_GT(ends[0].error.norm(), ends[2].error.norm());
  EXPECT_GT(ends[1].error.norm(), 15e-6);
  // A payload centred on the platform adds its weight: 800 + 400 kg sag 1.5×.
  e.compliance.payload_kg = 400.0;
  const std::vector<DwellEnd> loaded = RunStack("Lz", e, 3);
  for (std::size_t stop = 0; stop < ends.size(); ++stop) {
    EXPECT_NEAR(loaded[stop].error.z() / ends[stop].error.z(), 1.5, 0.01) << ends[stop].segment;
  }
}

TEST(RigEffects, ComplianceFollowsTheAccelerationInMotion) {
  const double k = 2e7, m = 800.0;
  const PlatformConfig nominal = Huang2021Config();
  auto trajectory = std::make_unique<TrajectorySequence>();
  PaperMotionOptions options;
  options.stops = 2;
  options.dwell_s = 0.2;
  options.max_speed_m_s = 0.35;
  AppendPaperMotion("Lz", PlatformModel(nominal).home_pose().ToVector(), options, trajectory.get());
  StackOptions stack;
  RigParameters rig = IdealRig(nominal);
  rig.effects.servo_lag.enabled = false;  // compliance alone, sample by sample
  rig.effects.compliance.enabled = true;
  rig.effects.compliance.stiffness_N_m.fill(k);
  rig.effects.compliance.mass_kg = m;
  stack.rig = rig;
  StackSimulation sim(nominal, std::move(trajectory), stack);
  double worst = 0.0, largest_dynamic = 0.0;
  StackSample previous;
  bool have_previous = false;
  while (!sim.Finished()) {
    const StackSample s = sim.Step();
    if (have_previous) {
      // The rig stands at this step's setpoint instant: compare with it.
      Vector6 q;
      for (int k2 = 0; k2 < 6; ++k2) q(k2) = s.setpoint.pose[k2];
      const double uz = LegAxisZ(sim.nominal_model(), q);
      const double predicted = -m * (9.81 + s.setpoint.acceleration[2]) / (6 * k * uz * uz);
      const double measured =
          previous.truth.observation_point_m[2] - sim.nominal_model().ObservationPoint(Pose::FromVector(q)).z();
      worst = std::max(worst, std::abs(measured - predicted) / std::abs(predicted));
      largest_dynamic = std::max(largest_dynamic, std::abs(s.setpoint.acceleration[2]) / 9.81);
    }
    previous = s;
    have_previous = true;
  }
  EXPECT_LT(worst, 0.1);
  EXPECT_GT(largest_dynamic, 0.02);  // the motion did accelerate (quintic, 0.35 m/s)
}

// With cooling negligible over the run, each screw warms by heating × its
// travel, and the legs grow by α·ΔT·L_screw: the platform rises over time.
TEST(RigEffects, ThermalDriftGrowsWithTheWorkDone) {
  RigEffects e = NoEffects();  // this effect alone
  e.thermal_drift.enabled = true;
  e.thermal_drift.heating_K_per_m = 2.0;
  e.thermal_drift.time_constant_s = 1e5;
  const std::vector<DwellEnd> ends = RunStack("Lz", e, 3);  // −0.5, 0, +0.5, home
  ASSERT_EQ(ends.size(), 4u);
  // Home is visited twice: after the first two moves and at the end.
  EXPECT_GT(ends[3].error.z(), ends[1].error.z() * 1.5);
  const Vector6 zero = Nominal().EncoderLengths(Nominal().home_pose());
  auto stroke = [&](const DwellEnd& d) {
    return std::abs((Nominal().EncoderLengths(Pose::FromVector(d.target)) - zero)(0));
  };
  const double travel = 2 * stroke(ends[0]) + 2 * stroke(ends[2]);  // home → −0.5 → 0 → +0.5 → home
  const double dl = 11.7e-6 * 2.0 * travel * 0.6;
  const double uz = LegAxisZ(Nominal(), ends[3].target);
  ExpectWithin10Percent(ends[3].error, Vector3(0.0, 0.0, dl / uz), ends[3].segment);
}

}  // namespace
}  // namespace edsp
