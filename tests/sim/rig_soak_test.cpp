// The virtual rig never loses its platform: random whole rigs (every static
// effect at once, as real rigs have them, a payload drawn up to the drives'
// rating) driven through the whole in-process stack over random moves
// between reachable poses. Every cycle the rig must find its pose, no drive
// may fault, no node may refuse a command, and the platform must stay where
// a rig with those effects can be (within 5 mm of the command: its sag, lag
// and errors reach 2 mm on the softest loops). And beyond the rating a drive
// faults and brakes: the platform stops, it does not fall.
#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <fmt/format.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_loads.h"
#include "edsp/kinematics/workspace.h"
#include "edsp/rig/payload_rating.h"
#include "edsp/sim/stack_simulation.h"

namespace edsp {
namespace {

using Rng = std::mt19937_64;

double Uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

// Every static effect class at once, in the ranges a rig team reports
// (leg offsets ±120 µm, joint centres σ 100 µm, leads ±250 ppm, backlash
// 15–40 µm, legs 15–30 N/µm), a payload up to the rating, a drive loop that
// may be soft.
RigEffects DrawWholeRig(Rng& rng, const PlatformModel& nominal, double* payload_kg) {
  RigEffects fx;
  fx.leg_offset.enabled = fx.joint_position.enabled = fx.lead_error.enabled = true;
  fx.backlash.enabled = fx.compliance.enabled = fx.periodic_lead_error.enabled = true;
  std::normal_distribution<double> joint(0.0, 100e-6);
  for (int i = 0; i < 6; ++i) {
    const auto leg = static_cast<std::size_t>(i);
    fx.leg_offset.offset_m[leg] = Uniform(rng, -120e-6, 120e-6);
    fx.lead_error.epsilon[leg] = Uniform(rng, -250e-6, 250e-6);
    fx.backlash.backlash_m[leg] = Uniform(rng, 15e-6, 40e-6);
    fx.compliance.stiffness_N_m[leg] = Uniform(rng, 15e6, 30e6);
    fx.periodic_lead_error.amplitude_m[leg] = Uniform(rng, 2e-6, 8e-6);
    fx.periodic_lead_error.phase_rad[leg] = Uniform(rng, 0.0, 6.28);
    for (int a = 0; a < 3; ++a) {
      fx.joint_position.base_m(a, i) = joint(rng);
      fx.joint_position.platform_m(a, i) = joint(rng);
    }
  }
  fx.compliance.com_m = Vector3(0.0, 0.0, Uniform(rng, 0.0, 0.3));
  fx.servo_lag.bandwidth_hz = Uniform(rng, 15.0, 60.0);
  fx.servo_lag.following_error_window_m = 0.002;  // a fault would show a drive that could not follow
  fx.servo_lag.integral_time_s = Uniform(rng, 0.0, 1.0) < 0.5 ? 0.0 : 5.0 / (6.2832 * fx.servo_lag.bandwidth_hz);
  const PayloadRating rating = RatePayload(nominal, fx.servo_lag, fx.compliance.com_m);
  *payload_kg = fx.compliance.mass_kg = Uniform(rng, 0.3, 1.0) * rating.payload_kg;
  return fx;
}

// Inside the workspace, the legs 3 mm inside their strokes (the PR
// compensation moves the command by up to 1.5 mm, which the bridge checks).
bool Reachable(const PlatformModel& model, const Vector6& q) {
  const Pose X_BM = Pose::FromVector(q);
  if (!CheckWorkspace(model, X_BM).ok()) return false;
  const Vector6 lengths = model.LegLengths(X_BM);
  const WorkspaceLimits& limits = model.config().limits;
  return lengths.minCoeff() >= limits.leg_min_m + 3e-3 && lengths.maxCoeff() <= limits.leg_max_m - 3e-3;
}

// The last reachable pose along a ray from home (to 0.1 mm): where the
// legs' loads and the joints' angles are at their worst.
Vector6 OnTheEdge(const PlatformModel& model, const Vector6& direction) {
  const Vector6 home = model.home_pose().ToVector();
  double inside = 0.0, outside = 1.0;
  if (Reachable(model, home + direction)) return home + direction;
  while ((outside - inside) * direction.head<3>().norm() > 1e-4) {
    const double mid = 0.5 * (inside + outside);
    (Reachable(model, home + mid * direction) ? inside : outside) = mid;
  }
  return home + inside * direction;
}

// Inside the workspace along the whole straight path (in pose coordinates,
// as the quintic move goes), with a margin for the planner's own check.
bool PathInside(const PlatformModel& model, const Vector6& from, const Vector6& to) {
  for (int k = 0; k <= 40; ++k) {
    if (!Reachable(model, from + (to - from) * (k / 40.0))) return false;
  }
  return true;
}

// Moves between random reachable poses, every other one to the edge of the
// workspace.
std::unique_ptr<TrajectorySequence> RandomMoves(Rng& rng, const PlatformModel& model, int moves) {
  auto sequence = std::make_unique<TrajectorySequence>();
  Vector6 at = model.home_pose().ToVector();
  sequence->Append("settle", std::make_unique<Dwell>(at, 0.1));
  for (int m = 0; m < moves;) {
    Vector6 direction;
    direction << Uniform(rng, -0.7, 0.7), Uniform(rng, -0.7, 0.7), Uniform(rng, -0.4, 0.4), Uniform(rng, -0.6, 0.6),
        Uniform(rng, -0.6, 0.6), Uniform(rng, -0.6, 0.6);
    const Vector6 to = m % 2 ? OnTheEdge(model, direction) : model.home_pose().ToVector() + 0.7 * direction;
    if (!PathInside(model, at, to)) continue;
    sequence->Append(fmt::format("move {}", m), std::make_unique<QuinticMove>(QuinticMove::WithinLimits(
                                                    at, to, Uniform(rng, 0.05, 0.15), Uniform(rng, 0.1, 0.25))));
    sequence->Append(fmt::format("dwell {}", m), std::make_unique<Dwell>(to, 0.05));
    at = to;
    ++m;
  }
  return sequence;
}

struct SoakResult {
  std::int64_t cycles = 0;
  bool lost = false;                 // the rig's pose not found
  bool faulted = false;              // a drive reported a fault
  double worst_error_m = 0.0;        // |true − commanded position of {M}|
  double moved_after_fault_m = 0.0;  // how far {M} went after the first fault
  std::string refused;               // the first fault a node raised (none expected)
};

SoakResult Soak(const PlatformConfig& nominal, const RigEffects& effects, std::unique_ptr<TrajectorySequence> moves) {
  StackOptions stack;
  RigParameters rig = IdealRig(nominal);
  rig.effects = effects;
  stack.rig = rig;
  StackSimulation sim(nominal, std::move(moves), stack);
  SoakResult r;
  Vector3 faulted_at = Vector3::Zero();
  while (!sim.Finished()) {
    if (r.refused.empty() && !sim.faults().empty()) r.refused = sim.faults().front().reason;
    StackSample s;
    try {
      s = sim.Step();
    } catch (const std::runtime_error&) {
      r.lost = true;
      return r;
    }
    ++r.cycles;
    const Vector3 commanded(s.setpoint.pose[0], s.setpoint.pose[1], s.setpoint.pose[2]);
    const Vector3 truth(s.truth.pose[0], s.truth.pose[1], s.truth.pose[2]);
    for (int i = 0; i < 6; ++i) {
      if (s.legs.drive_status[i] == leg_state_t::DRIVE_FAULT && !r.faulted) r.faulted = true, faulted_at = truth;
    }
    if (r.faulted) r.moved_after_fault_m = std::max(r.moved_after_fault_m, (truth - faulted_at).norm());
    r.worst_error_m = std::max(r.worst_error_m, (truth - commanded).norm());
  }
  return r;
}

TEST(RigSoak, WholeRigsUpToTheirRatingNeverLoseThePlatform) {
  const PlatformConfig nominal = Huang2021Config();
  const PlatformModel model(nominal);
  Rng rng(777);
  constexpr int kRigs = 12;
  int lost = 0, faulted = 0;
  std::int64_t cycles = 0;
  for (int r = 0; r < kRigs; ++r) {
    double payload_kg = 0.0;
    const RigEffects fx = DrawWholeRig(rng, model, &payload_kg);
    const SoakResult s = Soak(nominal, fx, RandomMoves(rng, model, 6));
    SCOPED_TRACE(fmt::format("rig {}: {:.0f} kg on {:.1f} N/um legs, {:.1f} Hz loop", r, payload_kg,
                             fx.compliance.stiffness_N_m[0] * 1e-6, fx.servo_lag.bandwidth_hz));
    lost += s.lost;
    faulted += s.faulted;
    cycles += s.cycles;
    EXPECT_FALSE(s.lost);
    EXPECT_FALSE(s.faulted);
    EXPECT_EQ(s.refused, "");
    EXPECT_LT(s.worst_error_m, 5e-3);  // sag, lag and errors: under 2 mm; a lost platform: metres
  }
  EXPECT_EQ(lost, 0);
  EXPECT_EQ(faulted, 0);
  EXPECT_GT(cycles, kRigs * 6 * 500);  // the moves really ran (each at least half a second)
}

// The rating is what the motors hold: the worst pose's static leg force at
// the rated payload is the rated share of the torque limit, recomputed here
// from the leg forces and the screw.
TEST(RigSoak, TheRatingIsTheTorqueTheWorstPoseNeeds) {
  const PlatformModel model(Huang2021Config());
  RigEffects::ServoLag drives;
  const PayloadRating rating = RatePayload(model, drives, Vector3(0, 0, 0.1));
  ASSERT_GT(rating.payload_kg, 0.0);
  const Vector6 f =
      LegForces(model, rating.worst_pose, Vector3::Zero(), rating.payload_kg, Vector3(0, 0, 0.1), Vector3(0, 0, -9.81));
  const double torque = f.cwiseAbs().maxCoeff() * 0.010 / (2.0 * 3.14159265358979 * drives.screw_efficiency);
  EXPECT_NEAR(torque, kRatedTorqueShare * drives.torque_limit_N_m, 1e-9 * drives.torque_limit_N_m);
  // Home is no worse than the worst pose, and the preset's default drives
  // carry the heaviest payload a rig team reports (1.2 t).
  const Vector6 home =
      LegForces(model, model.home_pose(), Vector3::Zero(), 1.0, Vector3(0, 0, 0.1), Vector3(0, 0, -9.81));
  EXPECT_LE(home.cwiseAbs().maxCoeff(), rating.worst_force_per_kg);
  EXPECT_GT(rating.payload_kg, 1200.0);
}

// Three times the rating: the motors cannot hold it at the workspace's
// edge. A drive faults and brakes; the platform stops where it is.
TEST(RigSoak, BeyondTheRatingADriveFaultsAndThePlatformStops) {
  const PlatformConfig nominal = Huang2021Config();
  const PlatformModel model(nominal);
  RigEffects fx;
  fx.compliance.enabled = true;
  fx.compliance.stiffness_N_m.fill(2e7);
  fx.compliance.com_m = Vector3(0, 0, 0.1);
  fx.compliance.mass_kg = 3.0 * RatePayload(model, fx.servo_lag, fx.compliance.com_m).payload_kg;
  fx.servo_lag.following_error_window_m = 0.002;
  auto moves = std::make_unique<TrajectorySequence>();
  Vector6 edge = model.home_pose().ToVector();
  edge(0) = 0.5;
  moves->Append("out", std::make_unique<QuinticMove>(model.home_pose().ToVector(), edge, 3.0));
  moves->Append("hold", std::make_unique<Dwell>(edge, 0.5));
  const SoakResult s = Soak(nominal, fx, std::move(moves));
  EXPECT_FALSE(s.lost);
  EXPECT_TRUE(s.faulted);
  // Stopped: the faulted leg's motor brakes and the bridge holds the others,
  // which stop from the path's speed (about 2 cm here), instead of running
  // the rest of the path (a quarter metre) on five legs.
  EXPECT_LT(s.moved_after_fault_m, 0.05);
}

}  // namespace
}  // namespace edsp
