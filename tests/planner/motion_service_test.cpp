// The motion service alone (no bus, no stack): what it refuses and why,
// that a refused or foreign request moves nothing, that copies of one
// request are acted on once, and, over 1 000 random moves, that every
// accepted path stays inside every limit in the setpoints it really sends
// while every path refused for the workspace really leaves it (both
// sampled here, apart from the planner's own check).
#include "edsp/planner/motion_service.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/pose.h"
#include "edsp/kinematics/workspace.h"
#include "edsp/reply_codes.h"
#include "edsp/request_kinds.h"
#include "motion_requests.h"        // tests/support
#include "served_motion_service.h"  // tests/support
#include "sanitized_build.h"        // tests/support

namespace edsp {
namespace {

using test_support::kServiceSession;
using test_support::kServiceT0;
using test_support::Served;
using test_support::Vec;

void ExpectRefused(const motion_reply_t& reply, const std::string& names) {
  EXPECT_FALSE(reply.accepted);
  EXPECT_NE(reply.reason.find(names), std::string::npos) << reply.reason;
}

// Every kind of request_kinds.h is acted on (none answered as unknown),
// planned beside the cycle exactly when it plans a path (the kinds that
// check a path whole, listed here apart from the table), and a kind no row
// has is refused by number.
TEST(MotionService, EveryKindInTheTableIsActedOnAndPlannedWhereItsRowSays) {
  const std::set<std::string> plans_a_path = {"move", "check", "run", "engage", "disengage", "jog"};
  for (const RequestKindRow& row : kRequestKinds) {
    EXPECT_EQ(row.plans_path, plans_a_path.count(std::string(row.name)) == 1) << row.name;
    Served s;
    const motion_reply_t reply = s.Ask(s.requests_.Make(row.kind, s.now_));
    EXPECT_EQ(reply.reason.find("unknown request kind"), std::string::npos) << row.name << ": " << reply.reason;
    EXPECT_EQ(reply.kind, row.kind);
    EXPECT_EQ(MotionService::IsQuick(s.requests_.Make(row.kind, s.now_)), !row.plans_path) << row.name;
  }
  Served s;
  const motion_reply_t unknown = s.Ask(s.requests_.Make(42, s.now_));
  ExpectRefused(unknown, "unknown request kind 42 (1 move … 11 jog)");
  EXPECT_TRUE(MotionService::IsQuick(s.requests_.Make(42, s.now_)));
}

TEST(MotionService, BadRequestsAreRefusedByNameAndMoveNothing) {
  Served s;
  auto& r = s.requests_;
  const Vector6 home = s.Held();
  ExpectRefused(s.Ask(r.Move(Vec(NAN, 0, 1.5), s.now_)), "non-finite");
  ExpectRefused(s.Ask(r.Move(Vec(0, 0, 1.5), s.now_, false, "nowhere")), "unknown frame \"nowhere\"");
  for (double speed : {1e6, -1.0, double(NAN), 0.11, 1e-320, 1e-9}) {
    motion_request_t m = r.Move(Vec(0.01, 0, 1.5), s.now_);
    m.speed_m_s = speed;
    ExpectRefused(s.Ask(m), "speed_max_m_s");
  }
  ExpectRefused(s.Ask(r.Move(Vec(0, 0, 3.0), s.now_)), "outside the workspace");
  motion_request_t crawl = r.Move(Vec(0.4, 0, 1.5), s.now_);
  crawl.speed_m_s = 0.0001;  // the slowest speed allowed, 0.4 m: over an hour
  ExpectRefused(s.Ask(crawl), "would last");
  motion_request_t hostile = r.Move(Vec(0.01, 0, 1.5), std::numeric_limits<std::int64_t>::min());
  ExpectRefused(s.Ask(hostile), "replayed");
  motion_request_t foreign = r.Move(Vec(0.01, 0, 1.5), s.now_);
  foreign.session_id = kServiceSession + 1;
  ExpectRefused(s.Ask(foreign), "from session 8");
  motion_request_t replayed = r.Move(Vec(0.01, 0, 1.5), s.now_ - 60'000'000);
  ExpectRefused(s.Ask(replayed), "replayed");
  motion_request_t unnumbered = r.Move(Vec(0.01, 0, 1.5), s.now_);
  unnumbered.request_id = 0;
  ExpectRefused(s.Ask(unnumbered), "request_id 0");
  ExpectRefused(s.Ask(r.Frame("base", Vec(0, 0, 0), s.now_)), "built in");
  ExpectRefused(s.Ask(r.Pivot(Vector3(0, NAN, 0), s.now_)), "pivot");
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(s.Held(), home) << "something moved";
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_REFUSED);
}

TEST(MotionService, WhileTheBridgeHoldsAMoveIsRefusedNamingTheReArm) {
  Served s;
  auto& r = s.requests_;
  s.Cycle(leg_state_t::DRIVE_HOLDING);
  ExpectRefused(s.Ask(r.Move(Vec(0.01, 0, 1.5), s.now_)), "edsp-ctl arm");
  EXPECT_NE(s.service_.Status(s.now_).state, motion_status_t::STATE_FAULT) << "a hold of one cycle is a blip";
  for (int k = 0; k < 50; ++k) s.Cycle(leg_state_t::DRIVE_HOLDING);
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_FAULT) << "a hold as long as the stale limit";
  EXPECT_TRUE(s.Ask(r.Make(motion_request_t::KIND_HALT, s.now_)).accepted) << "halt is always taken";
  s.Cycle();
  EXPECT_TRUE(s.Ask(r.Move(Vec(0.01, 0, 1.5), s.now_)).accepted) << "following again";
}

TEST(MotionService, BeforeTheBridgeFirstFollowsAMoveIsRefusedWithoutAskingForAReArm) {
  const PlatformModel model(Huang2021Config());
  MotionService service(model, Served::Options());
  test_support::MotionRequests r(kServiceSession);
  leg_state_t legs{};
  for (auto& d : legs.drive_status) d = leg_state_t::DRIVE_HOLDING;  // the bridge's start-up hold
  service.OnLegState(legs, kServiceT0);
  const motion_reply_t reply = service.Handle(r.Move(Vec(0.01, 0, 0), kServiceT0, true), kServiceT0);
  ExpectRefused(reply, "does not follow yet");
  EXPECT_EQ(reply.reason.find("edsp-ctl arm"), std::string::npos) << reply.reason;
}

TEST(MotionService, CopiesOfOneRequestGetOneReplyAndOneMotion) {
  Served s;
  auto& r = s.requests_;
  const motion_request_t move = r.Move(Vec(0.01, 0, 0), s.now_, true);
  const motion_reply_t first = s.Ask(move);
  s.Cycle();
  const motion_reply_t copy = s.Ask(move);
  EXPECT_TRUE(first.accepted);
  EXPECT_EQ(copy.seq, first.seq) << "the same reply";
  EXPECT_EQ(s.service_.Status(s.now_).queued, 0) << "acted on once";
  while (s.service_.busy()) s.Cycle();
  EXPECT_NEAR(s.Held()(0), 0.01, 1e-12) << "moved by 10 mm once, not twice";
}

TEST(MotionService, TwoClientsAtOnceAreServedInTurnEachWithItsOwnReply) {
  Served s;
  test_support::MotionRequests alice(kServiceSession), bob(kServiceSession);
  motion_request_t a = alice.Move(Vec(0.02, 0, 0), s.now_, true), b = bob.Move(Vec(0, 0.03, 0), s.now_, true);
  b.request_id += 1'000'000;  // each client numbers its own
  const motion_reply_t to_a = s.Ask(a), to_b = s.Ask(b);
  ASSERT_TRUE(to_a.accepted && to_b.accepted);
  EXPECT_EQ(to_a.request_id, a.request_id);
  EXPECT_EQ(to_b.request_id, b.request_id);
  EXPECT_NEAR(to_b.start_delay_s, to_a.duration_s, 1e-9) << "the second waits for the first";
  while (s.service_.busy()) s.Cycle();
  const Vector6 end = s.Held();
  EXPECT_NEAR(end(0), 0.02, 1e-12);
  EXPECT_NEAR(end(1), 0.03, 1e-12) << "both moves ran, the second from where the first ended";
}

// A jog is a relative move by its step along one axis: from the last
// target (queued behind a move still running), about the pivot, whatever
// its relative flag says.
// A program's setpoints say by their phase when they move and when they
// dwell (the segments' types: the labels agree, as the paper motions name
// their dwells), a hold before any motion is a hold, and after the program
// the hold keeps its last segment's label and phase.
TEST(MotionService, AProgramsSetpointsSayByTheirPhaseWhenTheyMoveAndWhenTheyDwell) {
  Served s;
  EXPECT_EQ(s.Cycle().phase, pose_setpoint_t::PHASE_HOLD);
  motion_request_t run = s.requests_.Make(motion_request_t::KIND_RUN, s.now_);
  run.motions = "Lz";
  ASSERT_TRUE(s.Ask(run).accepted);
  std::map<std::int8_t, int> cycles_in;
  pose_setpoint_t sp{};
  while (s.service_.busy()) {
    sp = s.Cycle();
    ++cycles_in[sp.phase];
    ASSERT_EQ(sp.phase == pose_setpoint_t::PHASE_DWELL, sp.trajectory.find("/dwell") != std::string::npos)
        << sp.trajectory;
    if (sp.phase == pose_setpoint_t::PHASE_DWELL) {
      ASSERT_EQ(Eigen::Map<const Vector6>(sp.velocity).norm(), 0.0);
    }
    if (sp.phase == pose_setpoint_t::PHASE_HOLD) {
      ASSERT_EQ(cycles_in[pose_setpoint_t::PHASE_MOVE], 0);
    }
  }
  EXPECT_GT(cycles_in[pose_setpoint_t::PHASE_MOVE], 1000);
  EXPECT_GT(cycles_in[pose_setpoint_t::PHASE_DWELL], 1000);
  const pose_setpoint_t held = s.Cycle();
  EXPECT_EQ(held.trajectory, "Lz/dwell home");
  EXPECT_EQ(held.phase, pose_setpoint_t::PHASE_DWELL);
}

TEST(MotionService, AJogLandsAtTheLastTargetPlusItsStepAlongItsAxis) {
  Served s;
  auto& r = s.requests_;
  const Vector6 home = s.Held();
  ASSERT_TRUE(s.Ask(r.Move(Vec(0.02, 0, 0), s.now_, true)).accepted);
  s.Cycle();
  ASSERT_TRUE(s.service_.busy());
  motion_request_t down = r.Jog(2, -0.004, s.now_);
  down.relative = false;  // a jog is relative anyway
  const motion_reply_t reply = s.Ask(down);
  ASSERT_TRUE(reply.accepted) << reply.reason;
  EXPECT_EQ(reply.kind, motion_request_t::KIND_JOG);
  EXPECT_GT(reply.start_delay_s, 0.0) << "queued behind the move";
  while (s.service_.busy()) s.Cycle();
  Vector6 end = s.Held();
  EXPECT_NEAR(end(0), home(0) + 0.02, 1e-12) << "from the move's target";
  EXPECT_NEAR(end(2), home(2) - 0.004, 1e-12);
  EXPECT_EQ(s.service_.Status(s.now_).activity, "jog z -0.004");

  // A turn about the pivot: the pivot stays where it is, yaw grows by the step.
  const Vector3 c(0.0, 0.0, 0.3);
  ASSERT_TRUE(s.Ask(r.Pivot(c, s.now_)).accepted);
  const Vector3 pivot_before = PointInBase(Pose::FromVector(end), c);
  ASSERT_TRUE(s.Ask(r.Jog(5, 0.01, s.now_, "home")).accepted);
  while (s.service_.busy()) s.Cycle();
  const Vector6 turned = s.Held();
  EXPECT_NEAR(turned(5), end(5) + 0.01, 1e-9);
  EXPECT_NEAR(turned(3), end(3), 1e-12);
  EXPECT_NEAR(turned(4), end(4), 1e-12);
  EXPECT_LT((PointInBase(Pose::FromVector(turned), c) - pivot_before).norm(), 1e-12) << "turned about the pivot";
}

// The status names the frame of the last move and gives its pose in {B}
// as it was defined (what the panel draws): zero for the base, the
// defining pose for a frame of the operator's.
TEST(MotionService, TheStatusCarriesTheLastMovesFrameAndItsPose) {
  Served s;
  auto& r = s.requests_;
  motion_status_t status = s.service_.Status(s.now_);
  EXPECT_EQ(status.frame, "base");
  for (double v : status.frame_pose) EXPECT_EQ(v, 0.0);
  Vector6 fixture;
  fixture << 0.05, -0.02, 1.45, 0.01, -0.02, 0.3;
  ASSERT_TRUE(s.Ask(r.Frame("fixture", fixture, s.now_)).accepted);
  ASSERT_TRUE(s.Ask(r.Move(Vec(0, 0, 0.01), s.now_, false, "fixture")).accepted);
  while (s.service_.busy()) s.Cycle();
  status = s.service_.Status(s.now_);
  EXPECT_EQ(status.frame, "fixture");
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(status.frame_pose[k], fixture(k), 1e-12) << k;
  // and the move landed in it: {M} at the frame's origin raised 10 mm along the frame's z
  const Vector6 held = s.Held();
  const Vector3 expected = fixture.head<3>() + RotationFromRpy(fixture.tail<3>()) * Vector3(0, 0, 0.01);
  EXPECT_LT((held.head<3>() - expected).norm(), 1e-9);
}

TEST(MotionService, AJogOfNoStepSeveralAxesOrMoreThanTenMillimetresIsRefusedAndMovesNothing) {
  Served s;
  auto& r = s.requests_;
  const Vector6 home = s.Held();
  const auto expect_invalid = [&](const motion_request_t& jog, const std::string& names) {
    const motion_reply_t reply = s.Ask(jog);
    ExpectRefused(reply, names);
    EXPECT_EQ(reply.code, static_cast<std::int8_t>(ReplyCode::kInvalid)) << reply.reason;
  };
  expect_invalid(r.Jog(0, 0.0, s.now_), "jog step is zero");
  expect_invalid(r.Jog(1, NAN, s.now_), "jog step along y = nan");
  expect_invalid(r.Jog(3, std::numeric_limits<double>::infinity(), s.now_), "give a finite step");
  motion_request_t two = r.Jog(0, 0.001, s.now_);
  two.pose[4] = 0.001;
  expect_invalid(two, "jog steps along x, pitch");
  expect_invalid(r.Jog(0, 0.0105, s.now_), "jog step along x = 0.0105 m is beyond 0.01 m");
  expect_invalid(r.Jog(4, -0.011, s.now_), "jog step along pitch = -0.011 rad is beyond 0.01 rad");
  expect_invalid(r.Jog(0, 0.001, s.now_, "nowhere"), "unknown frame \"nowhere\"");  // a move's checks too
  motion_request_t fast = r.Jog(0, 0.001, s.now_);
  fast.speed_m_s = 1e6;
  expect_invalid(fast, "speed_max_m_s");
  for (int k = 0; k < 100; ++k) ASSERT_EQ(s.Held(), home) << "something moved";
  EXPECT_EQ(s.service_.Status(s.now_).reason.rfind("jog refused: ", 0), 0u) << s.service_.Status(s.now_).reason;
}

TEST(MotionService, ACheckMovesNothingAndSaysWhatAMoveWould) {
  Served s;
  auto& r = s.requests_;
  motion_request_t check = r.Move(Vec(0.05, 0, 0), s.now_, true);
  check.kind = motion_request_t::KIND_CHECK;
  const motion_reply_t reply = s.Ask(check);
  EXPECT_TRUE(reply.accepted) << reply.reason;
  EXPECT_GT(reply.duration_s, 0.5);
  EXPECT_FALSE(s.service_.busy());
  check = r.Move(Vec(0, 0, 3.0), s.now_);
  check.kind = motion_request_t::KIND_CHECK;
  ExpectRefused(s.Ask(check), "leg");
}

// The geometric path of a move, apart from PivotPath: the pivot on its
// line, the rotation by quaternion slerp, the pose of {M} from both.
bool PathLeavesTheWorkspace(const PlatformModel& model, const Vector6& from, const Vector6& to, const Vector3& c) {
  const Pose a = Pose::FromVector(from), b = Pose::FromVector(to);
  const Eigen::Quaterniond qa(RotationFromRpy(a.rpy_rad)), qb(RotationFromRpy(b.rpy_rad));
  const Vector3 pa = PointInBase(a, c), pb = PointInBase(b, c);
  for (int k = 0; k <= 4000; ++k) {
    const double u = k / 4000.0;
    const Matrix3 R = qa.slerp(u, qb).toRotationMatrix();
    Pose p;
    p.rpy_rad = RpyFromRotation(R);
    p.p_BoMo_B = pa + u * (pb - pa) - R * c;
    if (!CheckWorkspace(model, p).ok()) return true;
  }
  return false;
}

// Drives three times as fast as the default moves: short moves, and paths
// whose legs would outrun the drives.
PlatformConfig FastMoves() {
  PlatformConfig c = Huang2021Config();
  c.motion.speed_max_m_s = 0.3, c.motion.speed_max_rad_s = 0.6;
  c.motion.accel_max_m_s2 = 1.5, c.motion.accel_max_rad_s2 = 3.0;
  c.motion.jerk_max_m_s3 = 15.0, c.motion.jerk_max_rad_s3 = 30.0;
  return c;
}

TEST(MotionService, OverRandomMovesEveryAcceptedPathStaysInsideAndEveryRefusalIsReal) {
  Served s(FastMoves());
  auto& r = s.requests_;
  const PlatformModel& model = s.model_;
  const double leg_speed_max = model.config().limits.leg_speed_max_m_s;
  const double leg_accel_max = model.config().motion.leg_accel_max_m_s2;
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> lin(-0.45, 0.45), height(1.15, 1.85), ang(-0.45, 0.45), piv(-0.4, 0.4);
  int accepted = 0, refused_workspace = 0, refused_legs = 0, crossing = 0;
  const int moves = test_support::kSanitizedBuild ? 200 : 1000;
  for (int n = 0; n < moves; ++n) {
    const Vector6 target = Vec(lin(rng), lin(rng), height(rng), ang(rng), ang(rng), ang(rng));
    if (!CheckWorkspace(model, Pose::FromVector(target)).ok()) {
      --n;  // reachable end poses only
      continue;
    }
    const Vector3 c(piv(rng), piv(rng), piv(rng));
    ASSERT_TRUE(s.Ask(r.Pivot(c, s.now_)).accepted);
    // The target as the pose of {M}: with pivot c the request names t = p − c + R·c.
    const Pose X = Pose::FromVector(target);
    Vector6 asked = target;
    asked.head<3>() = X.p_BoMo_B - c + RotationFromRpy(X.rpy_rad) * c;
    const Vector6 from = s.Held();
    const motion_reply_t reply = s.Ask(r.Move(asked, s.now_));
    if (!reply.accepted) {
      EXPECT_NE(reply.reason.find("at t = "), std::string::npos) << reply.reason;
      if (reply.reason.find("leg_speed_max") != std::string::npos ||
          reply.reason.find("leg_accel_max") != std::string::npos) {
        ++refused_legs;
      } else {
        ++refused_workspace;
        EXPECT_TRUE(PathLeavesTheWorkspace(model, from, target, c)) << reply.reason;
      }
      continue;
    }
    ++accepted;
    crossing += PathLeavesTheWorkspace(model, from, target, c);
    Vector6 before = model.LegLengths(Pose::FromVector(from)), speed_before = Vector6::Zero();
    while (s.service_.busy()) {
      const pose_setpoint_t sp = s.Cycle();
      const Pose p = Pose::FromVector(Eigen::Map<const Vector6>(sp.pose));
      ASSERT_TRUE(CheckWorkspace(model, p).ok()) << "move " << n << ": " << CheckWorkspace(model, p).Describe();
      const Vector6 length = model.LegLengths(p);
      const Vector6 speed = (length - before) / 1e-3;
      ASSERT_LE(speed.cwiseAbs().maxCoeff(), leg_speed_max) << "move " << n;
      ASSERT_LE(((speed - speed_before) / 1e-3).cwiseAbs().maxCoeff(), leg_accel_max * 1.01) << "move " << n;
      before = length, speed_before = speed;
    }
    EXPECT_LT((s.Held() - target).norm(), 1e-9) << "move " << n << " ended where asked";
  }
  EXPECT_EQ(crossing, 0) << "accepted paths that leave the workspace between samples";
  EXPECT_GT(accepted, 3 * moves / 10);
  EXPECT_GT(refused_workspace, 0) << "the draw must reach paths whose ends are reachable and middles not";
  EXPECT_GT(refused_legs, 0) << "and paths whose legs would outrun the drives";
  std::printf("random moves: %d accepted, %d refused for the workspace, %d for the legs\n", accepted, refused_workspace,
              refused_legs);
}

}  // namespace
}  // namespace edsp
