// A cueing source through the planner's motion service (no bus): engage
// moves to the neutral pose and only then do the setpoints become the
// source's; nothing else may move meanwhile; and every way the source can
// fail (silent, a NaN, a pose outside the workspace, a leg faster than the
// drives, another group's stream) either is ignored or ends the cueing
// holding the last valid pose, with the reason in the status.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "edsp/kinematics/config.h"
#include "edsp/motion_status_t.hpp"
#include "served_motion_service.h"  // tests/support

namespace edsp {
namespace {

using test_support::kServiceSession;
using test_support::Served;
using test_support::Vec;

// A cueing source's stream: one setpoint per call, numbered and stamped.
class CueSource {
 public:
  explicit CueSource(Served& s) : s_(s) {}
  void Send(const Vector6& pose, const Vector6& velocity = Vector6::Zero(), std::int64_t session = kServiceSession) {
    SendStamped(pose, velocity, s_.now_, session);
  }
  // A cue of instant `utime`, which need not be the service's now.
  void SendStamped(const Vector6& pose, const Vector6& velocity, std::int64_t utime,
                   std::int64_t session = kServiceSession) {
    pose_setpoint_t cue{};
    cue.utime = utime;
    cue.seq = ++seq_;
    cue.session_id = session;
    for (int k = 0; k < 6; ++k) {
      cue.pose[k] = pose(k);
      cue.velocity[k] = velocity(k);
    }
    cue.trajectory = "washout";
    s_.service_.OnCueSetpoint(cue, s_.now_);
  }

 private:
  Served& s_;
  std::int64_t seq_ = 0;
};

Vector6 PoseOf(const pose_setpoint_t& sp) { return Eigen::Map<const Vector6>(sp.pose); }
Vector6 VelocityOf(const pose_setpoint_t& sp) { return Eigen::Map<const Vector6>(sp.velocity); }

// Cycled until the planner follows, the source sending `neutral` all along.
void UntilCueing(Served& s, CueSource& source, const Vector6& neutral) {
  for (int cycle = 0; cycle < 20'000; ++cycle) {
    source.Send(neutral);
    s.Cycle();
    if (s.service_.Status(s.now_).state == motion_status_t::STATE_CUEING) return;
  }
  FAIL() << "never cueing: " << s.service_.Status(s.now_).reason;
}

// Engaged at `neutral`: the cycle after the engage move's end.
void EngageAt(Served& s, CueSource& source, const Vector6& neutral) {
  const motion_reply_t reply = s.Ask(s.requests_.Engage(neutral, s.now_, "sim"));
  ASSERT_TRUE(reply.accepted) << reply.reason;
  UntilCueing(s, source, neutral);
}

// The cue of a 0.5 Hz sway of 5 mm in y about `neutral` at time t.
Vector6 Sway(const Vector6& neutral, double t) {
  const double w = 2.0 * M_PI * 0.5;
  return neutral + Vec(0, 0.005 * std::sin(w * t), 0);
}

TEST(MotionServiceCueing, EngageMovesToTheNeutralPoseThenEverySetpointIsTheSources) {
  Served s;
  CueSource source(s);
  const Vector6 home = s.Held();
  const Vector6 neutral = home + Vec(0, 0, 0.02);
  const motion_reply_t reply = s.Ask(s.requests_.Engage(neutral, s.now_, "sim"));
  ASSERT_TRUE(reply.accepted) << reply.reason;
  EXPECT_NE(reply.reason.find("engaging cueing from sim"), std::string::npos) << reply.reason;
  // Until the move's end the setpoints are the move's, whatever the source sends.
  s.Cycle();
  const motion_status_t moving = s.service_.Status(s.now_);
  EXPECT_EQ(moving.state, motion_status_t::STATE_MOVING);
  EXPECT_EQ(moving.activity, "engage sim");
  source.Send(neutral + Vec(0.003, 0, 0));
  EXPECT_LT((PoseOf(s.Cycle()) - home).norm(), 0.001) << "a move starts from rest, not at the source's pose";
  UntilCueing(s, source, neutral);
  const motion_status_t cueing = s.service_.Status(s.now_);
  EXPECT_EQ(cueing.activity, "cueing sim");
  EXPECT_EQ(cueing.request_id, reply.request_id);
  // Then each cycle's setpoint is the source's latest, velocity included.
  for (int cycle = 0; cycle < 3000; ++cycle) {
    const double t = cycle * 1e-3;
    const Vector6 cue = Sway(neutral, t), velocity = Vec(0, 0.005 * M_PI * std::cos(M_PI * t), 0);
    source.Send(cue, velocity);
    const pose_setpoint_t sp = s.Cycle();
    ASSERT_LT((PoseOf(sp) - cue).cwiseAbs().maxCoeff(), 1e-15) << "cycle " << cycle;
    ASSERT_LT((VelocityOf(sp) - velocity).cwiseAbs().maxCoeff(), 1e-15) << "cycle " << cycle;
    ASSERT_EQ(sp.trajectory, "cueing");
    ASSERT_EQ(sp.phase, pose_setpoint_t::PHASE_CUEING);
  }
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
}

TEST(MotionServiceCueing, EngagingWhileAMotionRunsAndMovingWhileCueingAreRefused) {
  Served s;
  CueSource source(s);
  auto& r = s.requests_;
  const Vector6 home = s.Held();
  ASSERT_TRUE(s.Ask(r.Move(Vec(0.01, 0, 0), s.now_, true)).accepted);
  s.Cycle();
  const motion_reply_t engage = s.Ask(r.Engage(home, s.now_, "sim"));
  EXPECT_FALSE(engage.accepted);
  EXPECT_NE(engage.reason.find("is in progress"), std::string::npos) << engage.reason;
  while (s.service_.busy()) s.Cycle();
  EngageAt(s, source, home);
  const motion_reply_t move = s.Ask(r.Move(Vec(0.01, 0, 0), s.now_, true));
  EXPECT_FALSE(move.accepted);
  EXPECT_NE(move.reason.find("cueing from sim is engaged: disengage it first"), std::string::npos) << move.reason;
  const motion_reply_t again = s.Ask(r.Engage(home, s.now_, "other"));
  EXPECT_FALSE(again.accepted);
  EXPECT_NE(again.reason.find("cueing from sim is engaged"), std::string::npos) << again.reason;
  source.Send(home);
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING) << "refusals leave the cueing on";
}

TEST(MotionServiceCueing, ASilentSourceEndsItHoldingItsLastPoseAfterTheStaleLimit) {
  Served s;
  CueSource source(s);
  const Vector6 neutral = s.Held();
  EngageAt(s, source, neutral);
  Vector6 last;
  for (int cycle = 0; cycle < 500; ++cycle) {
    last = Sway(neutral, cycle * 1e-3);
    source.Send(last, Vec(0, 0.01, 0));
    s.Cycle();
  }
  // Within the limit the last cue is held as it came; past it, held still.
  const double stale_s = Served::Options().cue_stale_s;
  int cycles_followed = 0;
  pose_setpoint_t sp;
  do {
    sp = s.Cycle();
    ++cycles_followed;
  } while (s.service_.Status(s.now_).state == motion_status_t::STATE_CUEING && cycles_followed < 1000);
  EXPECT_NEAR(cycles_followed * 1e-3, stale_s, 1.5e-3) << "ended one cycle after the stale limit";
  const motion_status_t ended = s.service_.Status(s.now_);
  EXPECT_EQ(ended.state, motion_status_t::STATE_REFUSED);
  EXPECT_NE(ended.reason.find("cueing from sim ended: no EDSP_CUE_SETPOINT for"), std::string::npos) << ended.reason;
  EXPECT_EQ(ended.last_end, motion_status_t::END_STOPPED);
  // Held where the last cue led: carried along its 10 mm/s as the bridge rides through (10 ms), then still.
  const Vector6 held = PoseOf(sp);
  EXPECT_NEAR(held(1), last(1) + 0.01 * 10e-3, 1e-12);
  for (int cycle = 0; cycle < 100; ++cycle) {
    sp = s.Cycle();
    ASSERT_EQ(PoseOf(sp), held) << "holds the last valid pose";
    ASSERT_EQ(VelocityOf(sp).norm(), 0.0);
  }
  source.Send(neutral + Vec(0, 0.001, 0));
  EXPECT_EQ(PoseOf(s.Cycle()), held) << "a late cue moves nothing once ended";
  EXPECT_TRUE(s.Ask(s.requests_.Move(neutral, s.now_)).accepted) << "moves are served again";
}

TEST(MotionServiceCueing, AtNeutralItFollowsAtOnceAndWaitsForTheFirstCueUpToTheStaleLimit) {
  for (const bool cue_comes : {true, false}) {
    Served s;
    CueSource source(s);
    const Vector6 neutral = s.Held();
    const motion_reply_t reply = s.Ask(s.requests_.Engage(neutral, s.now_, "sim"));
    ASSERT_TRUE(reply.accepted) << reply.reason;
    EXPECT_NE(reply.reason.find("engaged at"), std::string::npos) << "no move to make: " << reply.reason;
    const double stale_s = Served::Options().cue_stale_s;
    for (int cycle = 0; cycle < static_cast<int>(stale_s * 1e3) - 2; ++cycle) {
      ASSERT_LT((PoseOf(s.Cycle()) - neutral).cwiseAbs().maxCoeff(), 1e-15) << "the neutral pose held meanwhile";
      ASSERT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
    }
    if (cue_comes) {
      source.Send(neutral + Vec(0, 0.0001, 0));
      EXPECT_NEAR(PoseOf(s.Cycle())(1), neutral(1) + 0.0001, 1e-15) << "followed";
      continue;
    }
    for (int cycle = 0; cycle < 4; ++cycle) s.Cycle();
    const motion_status_t ended = s.service_.Status(s.now_);
    EXPECT_EQ(ended.state, motion_status_t::STATE_REFUSED);
    EXPECT_NE(ended.reason.find("no EDSP_CUE_SETPOINT within 20 ms of the engage"), std::string::npos) << ended.reason;
  }
}

TEST(MotionServiceCueing, ACueThatComesACycleLateIsCarriedAlongItsVelocityNotStoodStill) {
  Served s;
  CueSource source(s);
  const Vector6 neutral = s.Held();
  EngageAt(s, source, neutral);
  const double speed = 0.3;  // m/s in y: 0.3 mm a cycle
  Vector6 previous = PoseOf(s.Cycle());
  for (int cycle = 0; cycle < 400; ++cycle) {
    const double t = (cycle + 1) * 1e-3;
    if (cycle % 7 != 3) source.Send(neutral + Vec(0, speed * t, 0), Vec(0, speed, 0));  // every 7th comes late
    const Vector6 now = PoseOf(s.Cycle());
    ASSERT_NEAR(now(1) - previous(1), speed * 1e-3, 1e-12) << "cycle " << cycle << ": an even step";
    previous = now;
  }
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
}

// A source that woke after a stall stamps its cue with an instant after the
// planner's cycle began (here up to 0.9 ms after): the setpoint is the cue
// carried back to the cycle's instant, so the legs step by what the vehicle
// moved in a cycle, not by the stamps' jitter on top (at a leg's top speed,
// two periods' travel in one cycle ended the cueing as a jump).
TEST(MotionServiceCueing, ACueStampedAfterTheCycleBeganIsTakenAtTheCyclesInstant) {
  Served s;
  CueSource source(s);
  const Vector6 neutral = s.Held();
  EngageAt(s, source, neutral);
  const double speed = 0.3;  // m/s in y
  const std::int64_t start_utime = s.now_;
  Vector6 previous = PoseOf(s.Cycle());
  for (int cycle = 0; cycle < 400; ++cycle) {
    const std::int64_t stamp = s.now_ + (cycle % 3) * 450;  // 0, 0.45, 0.9 ms after the cycle's start
    const double t = static_cast<double>(stamp - start_utime) * 1e-6;
    source.SendStamped(neutral + Vec(0, speed * t, 0), Vec(0, speed, 0), stamp);
    const Vector6 now = PoseOf(s.Cycle());
    ASSERT_NEAR(now(1) - previous(1), speed * 1e-3, 1e-12) << "cycle " << cycle << ": an even step";
    previous = now;
  }
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
}

// The source falls silent for longer than a cue is carried (a stall of its
// host), the vehicle going on meanwhile: its next cue is farther than the
// legs go in a cycle from the pose last followed. The stream itself was
// within the legs' speed, so the setpoints catch up at that speed, a cycle
// at a time, and follow the cues again (ending the cueing as a jump ended
// a live run on a machine half as fast).
TEST(MotionServiceCueing, AfterASourcesStallTheSetpointsCatchUpWithinTheLegsSpeed) {
  Served s;
  CueSource source(s);
  const Vector6 neutral = s.Held();
  EngageAt(s, source, neutral);
  const double speed = 0.4;  // m/s in y
  const std::int64_t start_utime = s.now_;
  const auto cue_at = [&](std::int64_t utime) -> Vector6 {
    return neutral + Vec(0, speed * static_cast<double>(utime - start_utime) * 1e-6, 0);
  };
  const double allowed = s.model_.config().limits.leg_speed_max_m_s * 1e-3 + 1e-6;
  Vector6 previous = PoseOf(s.Cycle());
  int caught_up_at = -1;
  for (int cycle = 0; cycle < 200; ++cycle) {
    const bool silent = cycle >= 50 && cycle < 70;  // 20 ms without a cue
    if (!silent) source.SendStamped(cue_at(s.now_), Vec(0, speed, 0), s.now_);
    const std::int64_t at = s.now_;
    const Vector6 now = PoseOf(s.Cycle());
    const double step = (s.model_.LegLengths(Pose::FromVector(now)) - s.model_.LegLengths(Pose::FromVector(previous)))
                            .cwiseAbs()
                            .maxCoeff();
    ASSERT_LE(step, allowed) << "cycle " << cycle;
    ASSERT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING)
        << "cycle " << cycle << ": " << s.service_.Status(s.now_).reason;
    if (cycle > 70 && caught_up_at < 0 && (now - cue_at(at)).cwiseAbs().maxCoeff() < 1e-12) caught_up_at = cycle;
    previous = now;
  }
  EXPECT_GT(caught_up_at, 70) << "the cue again, once caught up";
  EXPECT_LT(caught_up_at, 120);
}

// Engaged, swayed for a while: the pose last followed.
Vector6 Swayed(Served& s, CueSource& source, const Vector6& neutral) {
  EngageAt(s, source, neutral);
  Vector6 last;
  for (int cycle = 0; cycle < 200; ++cycle) {
    last = Sway(neutral, cycle * 1e-3);
    source.Send(last);
    s.Cycle();
  }
  return last;
}

void ExpectEndedHolding(Served& s, const Vector6& last, const std::string& reason) {
  const pose_setpoint_t sp = s.Cycle();
  const motion_status_t status = s.service_.Status(s.now_);
  EXPECT_EQ(status.state, motion_status_t::STATE_REFUSED);
  EXPECT_NE(status.reason.find(reason), std::string::npos) << status.reason;
  EXPECT_LT((PoseOf(sp) - last).cwiseAbs().maxCoeff(), 1e-15) << status.reason;
}

TEST(MotionServiceCueing, ACueNotFiniteOutsideTheWorkspaceOrTooFastForALegEndsItAtOnce) {
  {
    Served s;
    CueSource source(s);
    const Vector6 neutral = s.Held();
    const Vector6 last = Swayed(s, source, neutral);
    source.Send(Vec(std::numeric_limits<double>::quiet_NaN(), 0, neutral(2)));
    ExpectEndedHolding(s, last, "non-finite");
  }
  {
    Served s;
    CueSource source(s);
    const Vector6 neutral = s.Held();
    const Vector6 last = Swayed(s, source, neutral);
    source.Send(neutral + Vec(0, 0, 5.0));
    ExpectEndedHolding(s, last, "outside the workspace");
  }
  {  // a cue whose own velocity is faster than a leg may go: it is what a cue is carried along
    Served s;
    CueSource source(s);
    const Vector6 neutral = s.Held();
    const Vector6 last = Swayed(s, source, neutral);
    source.Send(last, Vec(0, 0, 1.0));
    ExpectEndedHolding(s, last, "by its velocity");
  }
  // A step in z: legs move by about its size; the limit is the config's
  // leg speed over the source's 1 ms, computed here by the legs' own lengths.
  for (const double share : {0.9, 1.2}) {
    Served s;
    CueSource source(s);
    const Vector6 neutral = s.Held();
    const Vector6 last = Swayed(s, source, neutral);
    const double allowed = s.model_.config().limits.leg_speed_max_m_s * 1e-3;
    const auto leg_step = [&](double dz) {
      return (s.model_.LegLengths(Pose::FromVector(last + Vec(0, 0, dz))) - s.model_.LegLengths(Pose::FromVector(last)))
          .cwiseAbs()
          .maxCoeff();
    };
    double dz = allowed;  // legs lean: a z step moves them less than itself
    while (leg_step(dz) < share * allowed) dz *= 1.001;
    source.Send(last + Vec(0, 0, dz));
    const pose_setpoint_t sp = s.Cycle();
    if (share < 1.0) {
      EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
      EXPECT_NEAR(PoseOf(sp)(2), last(2) + dz, 1e-15) << "followed";
    } else {
      const motion_status_t status = s.service_.Status(s.now_);
      EXPECT_EQ(status.state, motion_status_t::STATE_REFUSED);
      EXPECT_NE(status.reason.find("leg_speed_max_m_s"), std::string::npos) << status.reason;
      EXPECT_LT((PoseOf(sp) - last).cwiseAbs().maxCoeff(), 1e-15);
    }
  }
}

TEST(MotionServiceCueing, AnotherGroupsStreamAndOldCopiesAreIgnored) {
  Served s;
  CueSource source(s), intruder(s);
  const Vector6 neutral = s.Held();
  const Vector6 last = Swayed(s, source, neutral);
  intruder.Send(neutral + Vec(0, 0, 0.0001), Vector6::Zero(), kServiceSession + 1);
  const pose_setpoint_t sp = s.Cycle();
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_CUEING);
  EXPECT_LT((PoseOf(sp) - last).cwiseAbs().maxCoeff(), 1e-15) << "another session's cue moves nothing";
  // A copy with an older seq (the intruder's numbering is behind) changes nothing either.
  intruder.Send(neutral + Vec(0, 0, 0.0001));
  EXPECT_LT((PoseOf(s.Cycle()) - last).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(MotionServiceCueing, HaltHoldsWhereTheCueWasAndDisengageMovesToThePoseAsked) {
  Served s;
  CueSource source(s);
  auto& r = s.requests_;
  const Vector6 neutral = s.Held();
  const Vector6 last = Swayed(s, source, neutral);
  motion_request_t halt = r.Make(motion_request_t::KIND_HALT, s.now_);
  const motion_reply_t halted = s.Ask(halt);
  EXPECT_TRUE(halted.accepted);
  EXPECT_NE(halted.reason.find("halt: cueing from sim ended"), std::string::npos) << halted.reason;
  source.Send(neutral);
  const pose_setpoint_t sp = s.Cycle();
  EXPECT_LT((PoseOf(sp) - last).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(s.service_.Status(s.now_).last_end, motion_status_t::END_HALTED);

  EngageAt(s, source, neutral);
  for (int cycle = 0; cycle < 100; ++cycle) {
    source.Send(neutral);
    s.Cycle();
  }
  const Vector6 park = neutral + Vec(0, 0, -0.05);
  const motion_reply_t off = s.Ask(r.Disengage(park, s.now_));
  ASSERT_TRUE(off.accepted) << off.reason;
  EXPECT_NE(off.reason.find("cueing from sim disengaged"), std::string::npos) << off.reason;
  while (s.service_.busy()) s.Cycle();
  EXPECT_LT((s.Held() - park).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(s.service_.Status(s.now_).state, motion_status_t::STATE_HOLDING);
  const motion_reply_t none = s.Ask(r.Disengage(park, s.now_));
  EXPECT_FALSE(none.accepted);
  EXPECT_NE(none.reason.find("no cueing is engaged"), std::string::npos) << none.reason;
}

}  // namespace
}  // namespace edsp
