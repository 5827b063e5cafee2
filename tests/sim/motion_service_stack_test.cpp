// The planner's motion service driving the whole in-process stack
// (StackSimulation: kinematics, bridge, virtual rig), as an operator's
// script does on the live group: moves land on target in the rig's truth,
// rotations turn about the pivot, halt and stop stay within their bounds,
// and queued moves never step the velocity.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "edsp/kinematics/config.h"
#include "edsp/sim/stack_simulation.h"
#include "motion_requests.h"  // tests/support

namespace edsp {
namespace {

constexpr std::int64_t kSession = 1;

Vector6 Vec(const double (&a)[6]) {
  Vector6 v;
  for (int k = 0; k < 6; ++k) v(k) = a[k];
  return v;
}

class ServedStack {
 public:
  ServedStack() : sim_(Huang2021Config(), StackOptions{}), requests_(kSession) {
    Run(0.2);  // the bridge follows the held home pose
  }

  motion_reply_t Ask(const motion_request_t& r) { return sim_.motion().Handle(r, sim_.now_utime()); }
  test_support::MotionRequests& requests() { return requests_; }
  std::int64_t now() const { return sim_.now_utime(); }

  StackSample Step() {
    StackSample s = sim_.Step();
    samples_.push_back(s);
    return s;
  }
  void Run(double seconds) {
    for (int k = 0; k < std::lround(seconds * 1000); ++k) Step();
  }
  // Until nothing moves and the service calls it on target (or `limit_s`).
  bool RunUntilOnTarget(double limit_s = 30.0) {
    for (int k = 0; k < std::lround(limit_s * 1000); ++k) {
      Step();
      if (!sim_.motion().busy() && sim_.motion().Status(now()).on_target) return true;
    }
    return false;
  }
  motion_status_t Status() const { return const_cast<StackSimulation&>(sim_).motion().Status(now()); }
  std::vector<StackSample>& samples() { return samples_; }
  StackSimulation& sim() { return sim_; }

 private:
  StackSimulation sim_;
  test_support::MotionRequests requests_;
  std::vector<StackSample> samples_;
};

Vector6 TruthPose(const StackSample& s) {
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = s.truth.pose[k];
  return q;
}

Vector6 SetpointPose(const pose_setpoint_t& s) {
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = s.pose[k];
  return q;
}

// Position and angle between two poses at point c of {M}: computed from
// PointInBase and rotation matrices, apart from the service's frame algebra.
std::pair<double, double> Apart(const Vector6& a, const Vector6& b, const Vector3& c = Vector3::Zero()) {
  const Pose A = Pose::FromVector(a), B = Pose::FromVector(b);
  const Matrix3 d = RotationFromRpy(A.rpy_rad).transpose() * RotationFromRpy(B.rpy_rad);
  return {(PointInBase(A, c) - PointInBase(B, c)).norm(), std::acos(std::clamp((d.trace() - 1.0) / 2.0, -1.0, 1.0))};
}

// The pose of {M} in {B} an absolute move asks for, composed here with
// homogeneous matrices from the request's numbers.
Vector6 AskedPose(const motion_request_t& m, const std::map<std::string, Vector6>& frames, const Vector3& c) {
  const auto matrix = [](const Vector6& q) {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topLeftCorner<3, 3>() = RotationFromRpy(q.tail<3>());
    T.topRightCorner<3, 1>() = q.head<3>();
    return T;
  };
  const auto translation = [](const Vector3& v) {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topRightCorner<3, 1>() = v;
    return T;
  };
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = m.pose[k];
  Vector6 rotation_only = q;
  rotation_only.head<3>().setZero();
  const Eigen::Matrix4d X =
      matrix(frames.at(m.frame)) * translation(q.head<3>()) * translation(c) * matrix(rotation_only) * translation(-c);
  Vector6 out;
  out.head<3>() = X.topRightCorner<3, 1>();
  out.tail<3>() = RpyFromRotation(X.topLeftCorner<3, 3>());
  return out;
}

TEST(MotionServiceStack, AScriptOfMovesLandsEachOnItsTargetInTheRigsTruth) {
  ServedStack stack;
  auto& r = stack.requests();
  const Vector3 pivot(0.0, 0.0, 0.3);
  ASSERT_TRUE(stack.Ask(r.Frame("fixture", Vec({0.05, -0.02, 1.55, 0.0, 0.0, 0.3}), stack.now())).accepted);
  std::vector<motion_request_t> script = {
      r.Move(Vec({0.02, 0.0, 1.53, 0.0, 0.0, 0.0}), 0),
      r.Move(Vec({0.0, 0.0, 0.0, 0.0, 0.0, 0.05}), 0, true),
      r.Move(Vec({-0.03, 0.01, 1.50, 0.02, -0.01, 0.0}), 0),
      r.Move(Vec({0.0, 0.0, -0.01, 0.0, 0.0, 0.0}), 0, true, "home"),
      r.Move(Vec({0.01, 0.0, 0.0, 0.0, 0.0, 0.0}), 0, false, "home"),
      r.Move(Vec({0.0, 0.0, 0.0, 0.0, 0.0, 0.0}), 0, false, "fixture"),
      r.Move(Vec({0.0, 0.02, 0.0, 0.0, 0.0, 0.0}), 0, true, "fixture"),
      r.Move(Vec({0.0, 0.0, 0.0, 0.0, 0.03, 0.0}), 0, true, "fixture"),
  };
  int moves = 0;
  std::map<std::string, Vector6> frames = {{"", Vector6::Zero()},
                                           {"home", Vec({0, 0, 1.511, 0, 0, 0})},
                                           {"fixture", Vec({0.05, -0.02, 1.55, 0.0, 0.0, 0.3})}};
  Vector3 pivot_now = Vector3::Zero();
  auto play = [&](motion_request_t m) {
    m.utime = stack.now();
    const motion_reply_t reply = stack.Ask(m);
    ASSERT_TRUE(reply.accepted) << reply.reason;
    ASSERT_TRUE(stack.RunUntilOnTarget()) << "move " << m.request_id << " never on target";
    stack.Run(0.3);  // the rig's servo settles well past the tolerance
    const motion_status_t status = stack.Status();
    Vector6 target;
    for (int k = 0; k < 6; ++k) target(k) = status.pose_target[k];
    if (!m.relative) {
      // Where the operator asked, from the request alone: X_BW·T(t)·T(c)·R(r)·T(−c).
      const Vector6 expected = AskedPose(m, frames, pivot_now);
      EXPECT_LT(Apart(target, expected).first, 1e-9) << "move " << m.request_id << " went elsewhere";
      EXPECT_LT(Apart(target, expected).second, 1e-9) << "move " << m.request_id;
    }
    const auto [distance, angle] = Apart(TruthPose(stack.samples().back()), target);
    EXPECT_LT(distance, 1e-6) << "move " << m.request_id;
    EXPECT_LT(angle, 2e-6) << "move " << m.request_id;
    ++moves;
  };
  for (const motion_request_t& m : script) play(m);
  ASSERT_TRUE(stack.Ask(r.Pivot(pivot, stack.now())).accepted);
  pivot_now = pivot;
  for (const motion_request_t& m : script)
    play(r.Move(Vec({m.pose[0], m.pose[1], m.pose[2], m.pose[3], m.pose[4], m.pose[5]}), 0, m.relative, m.frame));
  for (int k = 0; k < 6; ++k)
    play(r.Move(Vec({0.0, 0.0, 0.0, 0.01 * (k % 3 == 0), 0.01 * (k % 3 == 1), 0.01 * (k % 3 == 2)}), 0, true,
                "fixture"));
  EXPECT_GE(moves, 20);
  EXPECT_TRUE(stack.sim().faults().empty()) << stack.sim().faults().front().reason;
}

TEST(MotionServiceStack, APureRotationTurnsAboutThePivotAlongTheWholePath) {
  ServedStack stack;
  auto& r = stack.requests();
  const Vector3 pivot(0.0, 0.0, 0.3);
  ASSERT_TRUE(stack.Ask(r.Pivot(pivot, stack.now())).accepted);
  for (const Vector6& turn : {Vec({0.0, 0.0, 0.0, 0.08, 0.0, 0.0}), Vec({0.0, 0.0, 0.0, 0.0, -0.06, 0.1}),
                              Vec({0.0, 0.0, 0.0, -0.05, 0.05, -0.2})}) {
    const Vector6 start = SetpointPose(stack.samples().back().setpoint);
    const std::size_t first = stack.samples().size();
    ASSERT_TRUE(stack.Ask(r.Move(turn, stack.now(), true)).accepted);
    ASSERT_TRUE(stack.RunUntilOnTarget());
    double worst = 0.0;
    for (std::size_t k = first; k < stack.samples().size(); ++k) {
      worst = std::max(worst, Apart(SetpointPose(stack.samples()[k].setpoint), start, pivot).first);
    }
    EXPECT_LT(worst, 1e-6) << "the pivot left its point";
    const double turned = Apart(SetpointPose(stack.samples().back().setpoint), start, pivot).second;
    EXPECT_GT(turned, 0.07) << "the platform did turn";
  }
}

// The setpoints' speed along x (m/s) and acceleration, by differences.
struct Kinematics1d {
  std::vector<double> x, v, a;
};
Kinematics1d AlongX(const std::vector<StackSample>& s, std::size_t from) {
  Kinematics1d k;
  for (std::size_t i = from; i < s.size(); ++i) k.x.push_back(s[i].setpoint.pose[0]);
  for (std::size_t i = 1; i < k.x.size(); ++i) k.v.push_back((k.x[i] - k.x[i - 1]) / 1e-3);
  for (std::size_t i = 1; i < k.v.size(); ++i) k.a.push_back((k.v[i] - k.v[i - 1]) / 1e-3);
  return k;
}

struct Braking {
  int reaction_cycles = -1;  // from the request to the first decelerating setpoint
  double distance_m = 0.0;   // from the request to rest
  double speed_m_s = 0.0;    // at the request
  double peak_decel_m_s2 = 0.0;
  double off_line_m = 0.0;           // the pivot's distance from its line (y, z)
  double peak_leg_accel_m_s2 = 0.0;  // of the setpoints' leg lengths (inverse kinematics)
};

Braking BrakeAtFullSpeed(std::int8_t kind) {
  ServedStack stack;
  auto& r = stack.requests();
  const MotionLimits limits = Huang2021Config().motion;
  EXPECT_TRUE(stack.Ask(r.Move(Vec({0.3, 0.0, 0.0, 0.0, 0.0, 0.0}), stack.now(), true)).accepted);
  // Cruising: 0.3 m at 0.1 m/s reaches full speed after v/a + a/j = 0.3 s.
  stack.Run(1.0);
  const std::size_t at = stack.samples().size() - 2;
  const Kinematics1d before = AlongX(stack.samples(), at);
  Braking b;
  b.speed_m_s = before.v.back();
  EXPECT_NEAR(b.speed_m_s, limits.speed_max_m_s, 1e-6) << "at full speed";
  // The request comes between cycles, at the next setpoint's time.
  const double x0 = stack.samples().back().setpoint.pose[0] + b.speed_m_s * 1e-3;
  EXPECT_TRUE(stack.Ask(r.Make(kind, stack.now())).accepted);
  const std::size_t first = stack.samples().size() - 1;
  for (int k = 0; k < 3000 && stack.sim().motion().busy(); ++k) stack.Step();
  const Kinematics1d after = AlongX(stack.samples(), first);
  for (std::size_t i = 0; i < after.v.size(); ++i) {
    if (after.v[i] < b.speed_m_s - 1e-9) {
      b.reaction_cycles = static_cast<int>(i) + 1;
      break;
    }
  }
  b.distance_m = stack.samples().back().setpoint.pose[0] - x0;
  for (double a : after.a) b.peak_decel_m_s2 = std::max(b.peak_decel_m_s2, -a);
  const PlatformModel model(Huang2021Config());
  for (std::size_t i = first + 2; i < stack.samples().size(); ++i) {
    const auto length = [&](std::size_t n) {
      return model.LegLengths(Pose::FromVector(SetpointPose(stack.samples()[n].setpoint)));
    };
    const Vector6 accel = (length(i) - 2.0 * length(i - 1) + length(i - 2)) / 1e-6;
    b.peak_leg_accel_m_s2 = std::max(b.peak_leg_accel_m_s2, accel.cwiseAbs().maxCoeff());
  }
  for (std::size_t i = first; i < stack.samples().size(); ++i) {
    const auto& p = stack.samples()[i].setpoint.pose;
    b.off_line_m = std::max(b.off_line_m, std::hypot(p[1], p[2] - stack.samples().front().setpoint.pose[2]));
  }
  EXPECT_EQ(stack.Status().last_end,
            kind == motion_request_t::KIND_HALT ? motion_status_t::END_HALTED : motion_status_t::END_STOPPED);
  EXPECT_EQ(stack.Status().state, motion_status_t::STATE_HOLDING);
  EXPECT_TRUE(stack.sim().faults().empty());
  return b;
}

TEST(MotionServiceStack, HaltDeceleratesWithinTheAccelerationLimitAndHoldsOnTheLine) {
  const MotionLimits l = Huang2021Config().motion;
  const Braking halt = BrakeAtFullSpeed(motion_request_t::KIND_HALT);
  EXPECT_GE(halt.reaction_cycles, 1) << "it never decelerated";
  EXPECT_LE(halt.reaction_cycles, 2) << "halt reaction";
  // Jerk-limited from full speed: v²/2a plus the ramps' v·a/2j, never less than v²/2a.
  const double v = halt.speed_m_s, a = l.accel_max_m_s2, j = l.jerk_max_m_s3;
  EXPECT_GE(halt.distance_m, v * v / (2 * a) - 1e-6);
  EXPECT_LE(halt.distance_m, v * v / (2 * a) + v * a / (2 * j) + 1e-6);
  EXPECT_LE(halt.peak_decel_m_s2, a * 1.001);
  EXPECT_LT(halt.off_line_m, 1e-9);
}

TEST(MotionServiceStack, StopIsShorterThanHaltWithinTheLegsAcceleration) {
  const MotionLimits l = Huang2021Config().motion;
  const Braking halt = BrakeAtFullSpeed(motion_request_t::KIND_HALT);
  const Braking stop = BrakeAtFullSpeed(motion_request_t::KIND_STOP);
  std::printf(
      "from %.4f m/s: halt after %d cycle(s), %.3f mm (v^2/2a %.3f mm), peak %.3f m/s^2; "
      "stop after %d cycle(s), %.3f mm, peak %.3f m/s^2, fastest leg %.3f m/s^2\n",
      halt.speed_m_s, halt.reaction_cycles, halt.distance_m * 1e3,
      halt.speed_m_s * halt.speed_m_s / (2 * l.accel_max_m_s2) * 1e3, halt.peak_decel_m_s2, stop.reaction_cycles,
      stop.distance_m * 1e3, stop.peak_decel_m_s2, stop.peak_leg_accel_m_s2);
  EXPECT_GE(stop.reaction_cycles, 1) << "it never decelerated";
  EXPECT_LE(stop.reaction_cycles, 2);
  EXPECT_LT(stop.distance_m, 0.5 * halt.distance_m);
  // The fastest leg decelerates at the legs' limit; the platform beyond the
  // move's own acceleration limit.
  EXPECT_LE(stop.peak_leg_accel_m_s2, l.leg_accel_max_m_s2 * 1.02);
  EXPECT_GT(stop.peak_leg_accel_m_s2, l.leg_accel_max_m_s2 * 0.9);
  EXPECT_GT(stop.peak_decel_m_s2, l.accel_max_m_s2 * 2.0);
  EXPECT_LT(stop.off_line_m, 1e-9);
}

TEST(MotionServiceStack, AHaltDuringAStopNeverTurnsThePlatformBack) {
  ServedStack stack;
  auto& r = stack.requests();
  ASSERT_TRUE(stack.Ask(r.Move(Vec({0.3, 0.0, 0.0, 0.0, 0.0, 0.0}), stack.now(), true)).accepted);
  stack.Run(1.0);
  ASSERT_TRUE(stack.Ask(r.Make(motion_request_t::KIND_STOP, stack.now())).accepted);
  stack.Run(0.005);  // braking hard, beyond the halt's own deceleration
  ASSERT_TRUE(stack.Ask(r.Make(motion_request_t::KIND_HALT, stack.now())).accepted);
  const std::size_t first = stack.samples().size() - 1;
  for (int k = 0; k < 3000 && stack.sim().motion().busy(); ++k) stack.Step();
  const Kinematics1d k = AlongX(stack.samples(), first);
  for (double v : k.v) ASSERT_GE(v, -1e-9) << "the platform went back";
  EXPECT_EQ(stack.Status().last_end, motion_status_t::END_STOPPED) << "the stop in progress went on";
}

TEST(MotionServiceStack, AMoveAskedForWhileAnotherRunsFollowsItWithoutAVelocityStep) {
  ServedStack stack;
  auto& r = stack.requests();
  const std::size_t first = stack.samples().size();
  const motion_reply_t one = stack.Ask(r.Move(Vec({0.05, 0.0, 0.0, 0.0, 0.0, 0.0}), stack.now(), true));
  stack.Run(0.2);
  const motion_reply_t two = stack.Ask(r.Move(Vec({-0.02, 0.0, 0.0, 0.0, 0.0, 0.0}), stack.now(), true));
  ASSERT_TRUE(one.accepted && two.accepted);
  EXPECT_NEAR(two.start_delay_s, one.duration_s - 0.2, 2e-3) << "queued behind the first";
  EXPECT_EQ(stack.Status().queued, 1);
  ASSERT_TRUE(stack.RunUntilOnTarget());
  const Kinematics1d k = AlongX(stack.samples(), first);
  double peak = 0.0;
  for (double a : k.a) peak = std::max(peak, std::abs(a));
  EXPECT_LE(peak, Huang2021Config().motion.accel_max_m_s2 * 1.001) << "no step in velocity";
  EXPECT_NEAR(stack.samples().back().setpoint.pose[0], 0.03, 1e-12);
}

}  // namespace
}  // namespace edsp
