// The motion service's cueing: engaging a cueing source (a checked move to
// its neutral pose), following its cues on EDSP_CUE_SETPOINT each cycle
// while each is valid, and ending it (disengage, halt, stop, or a cue it
// cannot follow: then holding the last valid pose). motion_service.h says
// what a client sees.
#include <algorithm>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "edsp/kinematics/workspace.h"
#include "edsp/planner/motion_request_checks.h"
#include "edsp/planner/motion_service.h"
#include "edsp/timing_contract.h"

namespace edsp {

namespace {

// The setpoints' trajectory name while they follow a cueing source.
constexpr char kCueingTrajectory[] = "cueing";
// How far ahead of a cue its setpoint may be carried along the cue's own
// velocity and acceleration: as long as the bridge rides through late
// commands (a cue a few cycles late must not make the setpoints stand, then
// jump by what the legs cannot do in a cycle).
constexpr double kCueLeadMax_s = timing::kRideThroughS;
// Two poses closer than this are one: no move between them is planned.
constexpr double kSamePose = 1e-9;
// A leg's step may exceed its speed × time by this much (rounding, the
// drives' encoder count), as the bridge's jump check allows.
constexpr double kLegStepSlack_m = 1e-6;
// A catch-up's step, of what the legs may go in the cycle: the legs' lengths
// are not linear in the pose, and a step scaled to the whole may overshoot.
constexpr double kCatchUpShare = 0.9;

// An engage's or a disengage's move: to its pose, in {B}, at its speeds.
motion_request_t MoveTo(const motion_request_t& r) {
  motion_request_t move = r;
  move.kind = motion_request_t::KIND_MOVE;
  move.relative = false;
  move.frame.clear();
  return move;
}

// The cue carried to `now_utime` by the source's stamp, along its velocity
// and acceleration: forward for a cue that came late (at most
// kCueLeadMax_s), back for one stamped after this cycle began (a source
// that woke after a stall and caught up, another host's clock). Taken at its
// own instant instead, a cue a period ahead would step the setpoints by two
// periods' travel in one cycle: at a leg's top speed, more than the drives
// may follow.
PoseSample CueAt(const pose_setpoint_t& cue, std::int64_t now_utime) {
  const double dt = std::clamp(static_cast<double>(now_utime - cue.utime) * 1e-6, -kCueLeadMax_s, kCueLeadMax_s);
  const Vector6 p = Eigen::Map<const Vector6>(cue.pose), v = Eigen::Map<const Vector6>(cue.velocity),
                a = Eigen::Map<const Vector6>(cue.acceleration);
  PoseSample s;
  s.pose = p + v * dt + 0.5 * a * dt * dt;
  s.velocity = v + a * dt;
  s.acceleration = a;
  return s;
}

}  // namespace

Problem MotionService::CueingProblem() const {
  if (!cueing_) return std::nullopt;
  return fmt::format("cueing from {} is engaged: disengage it first", cueing_->source);
}

motion_reply_t MotionService::Engage(const motion_request_t& r, std::int64_t now_utime, Lock& lock) {
  if (Problem p = CueingProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  if (current_ || !queue_.empty()) {
    return Reply(r, ReplyCode::kNotNow,
                 fmt::format("{} is in progress: engage once it has ended, or halt it",
                             current_ ? current_->motion.activity : queue_.front().activity));
  }
  if (Problem p = PoseProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  if (Problem p = BridgeProblem(now_utime)) return Reply(r, ReplyCode::kNotNow, *p);
  const std::string source = r.client.empty() ? "an unnamed source" : r.client;
  const Vector6 neutral = RequestPose(r);
  if ((hold_pose_ - neutral).cwiseAbs().maxCoeff() <= kSamePose) {  // no move to plan: following from now
    const WorkspaceCheck w = CheckWorkspace(model_, Pose::FromVector(neutral));
    if (!w.ok()) {
      return Reply(r, ReplyCode::kOutOfLimits,
                   fmt::format("the neutral pose {} is outside the workspace: {}", PoseText(neutral), w.Describe()));
    }
    StartCueing(source, r.request_id);
    ever_moved_ = true;
    StartFollowingIfEngaged(now_utime);
    return Reply(r, ReplyCode::kDone, fmt::format("cueing from {} engaged at {}", source, PoseText(neutral)));
  }
  motion_reply_t reply = Move(MoveTo(r), false, now_utime, lock);
  reply.kind = r.kind;
  if (!reply.accepted) return reply;
  queue_.back().activity = "engage " + source;  // the lock held since Move queued it
  StartCueing(source, r.request_id);
  reply.reason = fmt::format("engaging cueing from {}: {}", source, reply.reason);
  return reply;
}

motion_reply_t MotionService::Disengage(const motion_request_t& r, std::int64_t now_utime, Lock& lock) {
  if (!cueing_) return Reply(r, ReplyCode::kNotNow, "no cueing is engaged");
  if (Problem p = PoseProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  const std::string source = cueing_->source;
  EndCueing(now_utime, motion_status_t::END_COMPLETED);
  if ((PoseOf(PlannedEnd()).ToVector() - RequestPose(r)).cwiseAbs().maxCoeff() <= kSamePose) {
    return Reply(r, ReplyCode::kDone, fmt::format("cueing from {} disengaged at {}", source, PoseText(hold_pose_)));
  }
  motion_reply_t reply = Move(MoveTo(r), false, now_utime, lock);
  reply.kind = r.kind;
  reply.reason = fmt::format("cueing from {} disengaged; {}", source, reply.reason);
  return reply;
}

Problem MotionService::CueProblem(const pose_setpoint_t& cue, std::int64_t now_utime, FaultCode* code) const {
  const auto finite = [](const double* v) { return Eigen::Map<const Vector6>(v).allFinite(); };
  if (!finite(cue.pose) || !finite(cue.velocity) || !finite(cue.acceleration)) {
    *code = FaultCode::kNonFinite;
    return fmt::format("EDSP_CUE_SETPOINT seq {} has a non-finite value (NaN or infinity)", cue.seq);
  }
  const Vector6 q = Eigen::Map<const Vector6>(cue.pose);
  const WorkspaceCheck w = CheckWorkspace(model_, Pose::FromVector(q));
  if (!w.ok()) {
    *code = FaultCode::kOutsideWorkspace;
    return fmt::format("EDSP_CUE_SETPOINT seq {} asks for {}, outside the workspace: {}", cue.seq, PoseText(q),
                       w.Describe());
  }
  // Its own velocity no faster for a leg than the drives follow: it is what
  // the cue is carried along.
  const Vector6 v = Eigen::Map<const Vector6>(cue.velocity);
  if (const LegStep moving = LegStepBetween(q, q + v * 1e-3, 1e-3); moving.most_m > moving.allowed_m) {
    *code = FaultCode::kJump;
    return fmt::format(
        "EDSP_CUE_SETPOINT seq {} moves leg {} at {:.3f} m/s by its velocity (at most {:.3f} m/s at "
        "[limits] leg_speed_max_m_s)",
        cue.seq, moving.leg + 1, moving.most_m * 1e3, model_.config().limits.leg_speed_max_m_s);
  }
  // The source's stream while it is followed: no leg faster than the drives
  // follow from its last cue to this one, by their stamps, and the stamps no
  // further apart than the cues' arrivals allow (before, during the engage
  // move, nothing of it is followed).
  if (cueing_->following && cueing_->latest) {
    const pose_setpoint_t& last = *cueing_->latest;
    const double arrivals_s = static_cast<double>(now_utime - cueing_->latest_utime) * 1e-6 + kCueLeadMax_s;
    const double span_s =
        std::clamp(static_cast<double>(cue.utime - last.utime) * 1e-6, 1e-3, std::max(1e-3, arrivals_s));
    const LegStep step = LegStepBetween(Eigen::Map<const Vector6>(last.pose), q, span_s);
    if (step.most_m > step.allowed_m) {
      *code = FaultCode::kJump;
      return fmt::format(
          "EDSP_CUE_SETPOINT seq {} moves leg {} by {:.6f} m in {:.1f} ms after seq {} (at most {:.6f} m at "
          "[limits] leg_speed_max_m_s)",
          cue.seq, step.leg + 1, step.most_m, span_s * 1e3, last.seq, step.allowed_m);
    }
  }
  return std::nullopt;
}

MotionService::LegStep MotionService::LegStepBetween(const Vector6& from, const Vector6& to, double span_s) const {
  const Vector6 step = (model_.LegLengths(Pose::FromVector(to)) - model_.LegLengths(Pose::FromVector(from))).cwiseAbs();
  LegStep out;
  out.most_m = step.maxCoeff(&out.leg);
  out.allowed_m = model_.config().limits.leg_speed_max_m_s * span_s + kLegStepSlack_m;
  return out;
}

Problem MotionService::CueToFollow(std::int64_t now_utime, FaultCode* code, PoseSample* to) const {
  const EngagedCueing& c = *cueing_;
  *code = FaultCode::kStale;
  if (!c.latest) {  // the source's first cue may come a cycle after its engage was answered
    const double waited_s = static_cast<double>(now_utime - c.following_utime) * 1e-6;
    if (waited_s <= options_.cue_stale_s) return std::nullopt;
    return fmt::format("cueing from {} ended: no EDSP_CUE_SETPOINT within {:.0f} ms of the engage; holding", c.source,
                       options_.cue_stale_s * 1e3);
  }
  const double age_s = static_cast<double>(now_utime - c.latest_utime) * 1e-6;
  if (age_s > options_.cue_stale_s) {
    return fmt::format(
        "cueing from {} ended: no EDSP_CUE_SETPOINT for {:.0f} ms (at most {:.0f}); holding the last pose", c.source,
        age_s * 1e3, options_.cue_stale_s * 1e3);
  }
  // No leg faster than the drives follow since the cycle that followed
  // last (or the neutral pose, at the first): what the bridge checks too.
  *to = CueAt(*c.latest, now_utime);
  if (const WorkspaceCheck w = CheckWorkspace(model_, Pose::FromVector(to->pose)); !w.ok()) {
    *code = FaultCode::kOutsideWorkspace;
    return fmt::format(
        "cueing from {} ended: EDSP_CUE_SETPOINT seq {} carried to now asks for {}, outside the "
        "workspace: {}; holding the last pose",
        c.source, c.latest->seq, PoseText(to->pose), w.Describe());
  }
  const double since_s =
      c.followed_utime == 0 ? 1e-3 : std::max(1e-3, static_cast<double>(now_utime - c.followed_utime) * 1e-6);
  const LegStep step = LegStepBetween(hold_pose_, to->pose, since_s);
  if (step.most_m <= step.allowed_m) return std::nullopt;
  if (c.followed_utime != 0) {
    // Its stream was within the legs' speed (CueProblem), but the cue
    // carried to now is farther than they go in this cycle: a source or
    // this planner paused past the lead a cue is carried (a stall of the
    // host), and the vehicle went on meanwhile. Caught up at the legs'
    // speed, a cycle at a time, as the bridge rejoins a stream.
    const Vector6 gap = to->pose - hold_pose_;
    double share = kCatchUpShare * step.allowed_m / step.most_m;
    while (LegStepBetween(hold_pose_, hold_pose_ + gap * share, since_s).most_m > step.allowed_m) {
      share *= 0.5;  // the legs are not linear in the pose: a step that far, then less
    }
    to->pose = hold_pose_ + gap * share;
    to->velocity = gap * share / since_s;  // what the setpoints do, for the kinematics' feed-forward
    to->acceleration = Vector6::Zero();
    return std::nullopt;
  }
  *code = FaultCode::kJump;
  return fmt::format(
      "cueing from {} ended: EDSP_CUE_SETPOINT seq {} moves leg {} by {:.6f} m from the neutral pose in {:.1f} ms "
      "(at most {:.6f} m at [limits] leg_speed_max_m_s); holding the last pose",
      c.source, c.latest->seq, step.leg + 1, step.most_m, since_s * 1e3, step.allowed_m);
}

void MotionService::EndCueing(std::int64_t now_utime, std::int8_t end, std::optional<CueFault> fault) {
  if (!cueing_) return;
  if (cueing_->following) {
    last_end_ = end;
    ended_utime_ = now_utime;
    within_since_ = 0;
  }
  cueing_.reset();
  if (fault) {
    refused_ = fault->reason;
    cue_fault_ = std::move(fault);
  }
  Changed();
}

void MotionService::StartCueing(const std::string& source, std::int64_t request_id) {
  cueing_.emplace();
  cueing_->source = source;
  cueing_->request_id = request_id;
}

void MotionService::StartFollowingIfEngaged(std::int64_t now_utime) {
  if (!cueing_ || cueing_->following || current_ || !queue_.empty()) return;
  cueing_->following = true;
  cueing_->following_utime = now_utime;
  request_id_ = cueing_->request_id;
  activity_ = "cueing " + cueing_->source;
  Changed();
}

void MotionService::OnCueSetpoint(const pose_setpoint_t& cue, std::int64_t now_utime) {
  const std::lock_guard<std::mutex> lock(mutex_);
  // Another group's, or nothing engaged: not this service's to follow.
  if (!cueing_ || cue.session_id != options_.session_id) return;
  if (cueing_->latest && cue.seq <= cueing_->latest->seq) return;  // a copy or one overtaken: the newer stands
  FaultCode code{};
  if (Problem p = CueProblem(cue, now_utime, &code)) {
    EndCueing(now_utime, motion_status_t::END_STOPPED,
              CueFault{code, fmt::format("cueing from {} ended: {}; holding the last pose", cueing_->source, *p)});
    return;
  }
  cueing_->latest = cue;
  cueing_->latest_utime = now_utime;
}

std::optional<MotionService::CueFault> MotionService::TakeCueFault() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::optional<CueFault> fault;
  fault.swap(cue_fault_);
  return fault;
}

void MotionService::FollowCue(std::int64_t now_utime, PoseSample* sample) {
  FaultCode code{};
  PoseSample cue;
  if (Problem why = CueToFollow(now_utime, &code, &cue)) {
    EndCueing(now_utime, motion_status_t::END_STOPPED, CueFault{code, std::move(*why)});
    return;
  }
  if (!cueing_->latest) return;  // none yet, within the stale limit: the neutral pose held
  *sample = cue;
  hold_pose_ = sample->pose;
  cueing_->followed_utime = now_utime;
  hold_name_ = kCueingTrajectory;
  hold_phase_ = pose_setpoint_t::PHASE_CUEING;
  hold_segment_ = cueing_->latest->segment;  // the vehicle packet it came from: the cueing delay's trace
}

}  // namespace edsp
