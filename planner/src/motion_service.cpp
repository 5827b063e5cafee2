#include "edsp/planner/motion_service.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "edsp/kinematics/workspace.h"
#include "edsp/planner/csv_trajectory.h"
#include "edsp/planner/motion_request_checks.h"
#include "edsp/planner/planner.h"
#include "edsp/request_kinds.h"
#include "edsp/timing_contract.h"

namespace edsp {

namespace {

std::int64_t Micros(double s) { return std::llround(s * 1e6); }

// The pivot's distance and the rotation's angle between two poses.
std::pair<double, double> PoseError(const Vector6& a, const Vector6& b, const Vector3& pivot_M) {
  const Transform A = TransformOf(Pose::FromVector(a)), B = TransformOf(Pose::FromVector(b));
  const double distance = (A * pivot_M - B * pivot_M).norm();
  const double angle = Eigen::AngleAxisd(Matrix3(A.linear().transpose() * B.linear())).angle();
  return {distance, std::abs(angle)};
}

}  // namespace

MotionService::MotionService(const PlatformModel& model, MotionServiceOptions options)
    : model_(model),
      options_(std::move(options)),
      config_limits_(ConfigMoveLimits(model_)),
      default_limits_(config_limits_),
      hold_pose_(model_.home_pose().ToVector()),
      commanded_pose_(hold_pose_) {
  frames_["base"] = WorkFrame{};
  frames_["home"] = WorkFrame{"home", TransformOf(model_.home_pose())};
}

void MotionService::StartProgram(std::unique_ptr<TrajectorySequence> program, const std::string& name) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (program == nullptr || program->size() == 0) throw std::invalid_argument("planner: empty trajectory");
  const TrajectorySequence* sequence = program.get();
  PlannedMotion m = PlanProgram(model_, std::move(program), default_limits_, options_.check_rate_hz);
  if (!m.check.ok()) throw std::invalid_argument(TrajectoryViolation(*sequence, m.check));
  m.activity = "run " + name;
  queue_.push_back(std::move(m));
  ever_moved_ = true;
  Changed();
}

bool MotionService::IsQuick(const motion_request_t& r) {
  const RequestKindRow* row = FindRequestKind(r.kind);
  return row == nullptr || !row->plans_path;  // an unknown kind is refused at once
}

motion_reply_t MotionService::Handle(const motion_request_t& r, std::int64_t now_utime) {
  Lock lock(mutex_);
  const auto answer = requests_.Handle(
      r, now_utime, [&](ReplyCode code, std::string reason) { return Reply(r, code, std::move(reason)); },
      [&] { return Act(r, now_utime, lock); });
  if (answer.acted) {
    refused_.reset();
    if (!answer.reply.accepted) refused_ = RequestKindName(r.kind) + " refused: " + answer.reply.reason;
    Changed();
  }
  return answer.reply;
}

// What each kind does: a kind's row in request_kinds.h and its case here.
motion_reply_t MotionService::Act(const motion_request_t& r, std::int64_t now_utime, Lock& lock) {
  switch (r.kind) {
    case motion_request_t::KIND_MOVE: return Move(r, false, now_utime, lock);
    case motion_request_t::KIND_CHECK: return Move(r, true, now_utime, lock);
    case motion_request_t::KIND_RUN: return Run(r, now_utime, lock);
    case motion_request_t::KIND_HALT: return Decelerate(r, false, now_utime);
    case motion_request_t::KIND_STOP: return Decelerate(r, true, now_utime);
    case motion_request_t::KIND_FRAME: return DefineFrame(r);
    case motion_request_t::KIND_PIVOT: return SetPivot(r);
    case motion_request_t::KIND_LIMITS: return SetLimits(r);
    case motion_request_t::KIND_ENGAGE: return Engage(r, now_utime, lock);
    case motion_request_t::KIND_DISENGAGE: return Disengage(r, now_utime, lock);
    case motion_request_t::KIND_JOG: return Jog(r, now_utime, lock);
  }
  const RequestKindRow& first = kRequestKinds[0];
  const RequestKindRow& last = kRequestKinds[std::size(kRequestKinds) - 1];
  return Reply(
      r, ReplyCode::kInvalid,
      fmt::format("unknown request kind {} ({} {} … {} {})", r.kind, first.kind, first.name, last.kind, last.name));
}

motion_reply_t MotionService::Reply(const motion_request_t& r, ReplyCode code, std::string reason, double duration_s,
                                    double start_delay_s) const {
  motion_reply_t reply{};
  reply.session_id = options_.session_id;
  reply.request_id = r.request_id;
  reply.kind = r.kind;
  reply.code = static_cast<std::int8_t>(code);
  reply.accepted = code == ReplyCode::kDone;
  reply.reason = std::move(reason);
  reply.duration_s = duration_s;
  reply.start_delay_s = start_delay_s;
  return reply;
}

Problem MotionService::BridgeProblem(std::int64_t now_utime) const {
  if (leg_state_utime_ == 0) return "no EDSP_LEG_STATE from the actuator bridge yet: is it running?";
  const double silent_s = static_cast<double>(now_utime - leg_state_utime_) * 1e-6;
  if (silent_s > options_.bridge_stale_s) {
    return fmt::format("no EDSP_LEG_STATE from the actuator bridge for {:.2f} s: is it running?", silent_s);
  }
  if (!bridge_holds_.empty() && !bridge_followed_) {
    return "the actuator bridge does not follow yet (" + bridge_holds_ +
           " since it started): ask again once it follows (no re-arm needed)";
  }
  if (!bridge_holds_.empty()) {
    return "the actuator bridge holds the legs (" + bridge_holds_ + "): re-arm it first (edsp-ctl arm)";
  }
  return std::nullopt;
}

Problem MotionService::QueueProblem() const {
  if (queue_.size() < options_.queue_max) return std::nullopt;
  return fmt::format("{} motions already queued: wait, or halt", queue_.size());
}

const WorkFrame* MotionService::FindFrame(const std::string& name) const {
  const auto it = frames_.find(name.empty() ? "base" : name);
  return it == frames_.end() ? nullptr : &it->second;
}

Transform MotionService::PlannedEnd() const {
  if (!queue_.empty()) return TransformOf(Pose::FromVector(queue_.back().end_pose()));
  if (current_) return TransformOf(Pose::FromVector(current_->motion.end_pose()));
  return TransformOf(Pose::FromVector(hold_pose_));
}

double MotionService::TimeToIdle(std::int64_t now_utime) const {
  double left = 0.0;
  if (current_) {
    const double elapsed =
        current_->start_utime == 0 ? 0.0 : static_cast<double>(now_utime - current_->start_utime) * 1e-6;
    left += std::max(0.0, current_->motion.duration_s() - elapsed);
  }
  for (const PlannedMotion& m : queue_) left += m.duration_s();
  return left;
}

motion_reply_t MotionService::Move(const motion_request_t& r, bool check_only, std::int64_t now_utime, Lock& lock) {
  if (Problem p = PoseProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  const WorkFrame* found = FindFrame(r.frame);
  if (found == nullptr) {
    std::string known;
    for (const auto& [name, f] : frames_) known += (known.empty() ? "" : ", ") + name;
    return Reply(r, ReplyCode::kInvalid,
                 fmt::format("unknown frame \"{}\" (known: {}; define one with edsp-ctl frame)", r.frame, known));
  }
  const WorkFrame frame = *found;
  const Vector3 pivot = pivot_M_;
  MoveLimits limits = default_limits_;
  if (Problem p = SpeedLimitsProblem(r, config_limits_, &limits)) {
    return Reply(r, ReplyCode::kInvalid, *p);
  }
  if (!check_only) {
    if (Problem p = CueingProblem()) return Reply(r, ReplyCode::kNotNow, *p);
    if (Problem p = BridgeProblem(now_utime)) return Reply(r, ReplyCode::kNotNow, *p);
    if (Problem p = QueueProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  }
  const Transform from = PlannedEnd();
  FramedPose to = FramedPoseOf(RequestPose(r));
  if (r.relative) {
    const FramedPose now = InFrame(frame, pivot, from);
    to.t = now.t + to.t;
    to.R = to.R * now.R;
  }
  const Vector6 target = PoseOf(PlatformPose(frame, pivot, to)).ToVector();
  const WorkspaceCheck end = CheckWorkspace(model_, Pose::FromVector(target));
  if (!end.ok()) {
    return Reply(
        r, ReplyCode::kOutOfLimits,
        fmt::format("target {} (in {}) is outside the workspace: {}", PoseText(target), frame.name, end.Describe()));
  }
  // Planned and checked without the lock: setpoints go on meanwhile.
  const std::uint64_t decelerations = decelerations_;
  lock.unlock();
  PlannedMotion m = PlanMove(model_, frame, pivot, from, to, limits, options_.check_rate_hz);
  lock.lock();
  if (m.check.limit == PathLimit::kDuration) return Reply(r, ReplyCode::kOutOfLimits, m.check.Describe());
  if (!m.check.ok()) {
    return Reply(r, ReplyCode::kOutOfLimits,
                 fmt::format("the path to {} crosses a limit (both ends are reachable) {}", PoseText(target),
                             m.check.Describe()));
  }
  m.request_id = r.request_id;
  const std::string what =
      fmt::format("{} to {} in {} ({}) in {:.3f} s, {}", check_only ? "would move" : "moves", PoseText(target),
                  frame.name, m.path->Extent(), m.duration_s(), m.check.Describe());
  if (check_only) return Reply(r, ReplyCode::kDone, what, m.duration_s(), TimeToIdle(now_utime));
  if (Problem p = PlanOutdated(from, decelerations)) return Reply(r, ReplyCode::kNotNow, *p);
  if (Problem p = QueueProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  std::deque<PlannedMotion> motions;
  motions.push_back(std::move(m));
  motion_reply_t reply = Enqueue(r, std::move(motions), now_utime);
  reply.reason = what;
  return reply;
}

motion_reply_t MotionService::Jog(const motion_request_t& r, std::int64_t now_utime, Lock& lock) {
  if (Problem p = JogProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  motion_request_t move = r;
  move.relative = true;  // whatever the client set: a jog is from the last target
  motion_reply_t reply = Move(move, false, now_utime, lock);
  if (!reply.accepted) return reply;
  int axis = 0;
  while (r.pose[axis] == 0.0) ++axis;  // JogProblem found exactly one
  // The lock held since Move queued it.
  queue_.back().activity = fmt::format("jog {} {:+g}", kJogAxes[axis], r.pose[axis]);
  return reply;
}

Problem MotionService::PlanOutdated(const Transform& from, std::uint64_t decelerations) const {
  if (decelerations != decelerations_) return "a halt or stop came while the path was checked: ask again";
  if (!PlannedEnd().isApprox(from, 1e-12)) {
    return "another motion was queued while the path was checked (it would start elsewhere): ask again";
  }
  return std::nullopt;
}

motion_reply_t MotionService::Run(const motion_request_t& r, std::int64_t now_utime, Lock& lock) {
  if (Problem p = CueingProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  if (Problem p = BridgeProblem(now_utime)) return Reply(r, ReplyCode::kNotNow, *p);
  if (Problem p = QueueProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  if (Problem p = ProgramProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  const Transform from = PlannedEnd();
  const MoveLimits limits = default_limits_;
  const std::uint64_t decelerations = decelerations_;
  lock.unlock();  // the program built, planned and checked without the lock, as a move
  std::deque<PlannedMotion> motions;
  const std::string name = !r.motions.empty() ? r.motions : r.csv_origin.empty() ? "csv" : r.csv_origin;
  Problem problem;
  ReplyCode problem_code = ReplyCode::kOutOfLimits;  // a path that crosses a limit, unless it cannot be built
  try {
    std::unique_ptr<TrajectorySequence> program;
    if (!r.motions.empty()) {
      program = options_.programs
                    ? options_.programs(r.motions)
                    : PaperMotionSequence(MotionNames(r.motions), model_.home_pose().ToVector(), PaperMotionOptions{});
    } else {
      program = std::make_unique<TrajectorySequence>();
      program->Append(name, std::make_unique<CsvTrajectory>(CsvTrajectory::Parse(r.csv_text, name)));
    }
    const Vector6 start = program->Sample(0.0).pose;
    if ((PoseOf(from).ToVector() - start).cwiseAbs().maxCoeff() > 1e-9) {
      PlannedMotion approach =
          PlanMove(model_, WorkFrame{}, Vector3::Zero(), from, FramedPoseOf(start), limits, options_.check_rate_hz);
      if (!approach.check.ok()) problem = "the approach to the program's start " + approach.check.Describe();
      approach.activity = "approach";
      approach.request_id = r.request_id;
      motions.push_back(std::move(approach));
    }
    const TrajectorySequence* sequence = program.get();
    PlannedMotion played = PlanProgram(model_, std::move(program), limits, options_.check_rate_hz);
    if (!problem && !played.check.ok()) problem = TrajectoryViolation(*sequence, played.check);
    played.activity = "run " + name;
    played.request_id = r.request_id;
    motions.push_back(std::move(played));
  } catch (const std::exception& e) {
    problem = e.what();
    problem_code = ReplyCode::kInvalid;
  }
  lock.lock();
  if (problem) return Reply(r, problem_code, *problem);
  if (Problem p = PlanOutdated(from, decelerations)) return Reply(r, ReplyCode::kNotNow, *p);
  if (Problem p = QueueProblem()) return Reply(r, ReplyCode::kNotNow, *p);
  return Enqueue(r, std::move(motions), now_utime);
}

motion_reply_t MotionService::Enqueue(const motion_request_t& r, std::deque<PlannedMotion> motions,
                                      std::int64_t now_utime) {
  const double delay = TimeToIdle(now_utime);
  double duration = 0.0;
  for (PlannedMotion& m : motions) {
    duration += m.duration_s();
    queue_.push_back(std::move(m));
  }
  ever_moved_ = true;
  return Reply(r, ReplyCode::kDone,
               fmt::format("{} in {:.3f} s, starting in {:.3f} s", queue_.back().activity, duration, delay), duration,
               delay);
}

motion_reply_t MotionService::Decelerate(const motion_request_t& r, bool stop, std::int64_t now_utime) {
  ++decelerations_;
  const std::int8_t end = stop ? motion_status_t::END_STOPPED : motion_status_t::END_HALTED;
  const std::string what = stop ? "stop" : "halt";
  if (cueing_ && cueing_->following) {
    const std::string source = cueing_->source;
    EndCueing(now_utime, end);
    return Reply(r, ReplyCode::kDone,
                 fmt::format("{}: cueing from {} ended, holding {}", what, source, PoseText(hold_pose_)));
  }
  cueing_.reset();  // an engage move halted or stopped: no cueing after it
  const std::size_t cancelled = queue_.size();
  queue_.clear();
  const std::string queued = cancelled == 0 ? "" : fmt::format("; {} queued motion(s) cancelled", cancelled);
  if (cancelled > 0) last_end_ = end;
  if (!current_) return Reply(r, ReplyCode::kDone, "nothing moving" + queued);
  Running& c = *current_;
  if (c.start_utime == 0 || c.start_utime > now_utime) {  // not started: it never will
    current_.reset();
    last_end_ = end;
    return Reply(r, ReplyCode::kDone, fmt::format("{}: the motion had not started{}", what, queued));
  }
  // A halt while stopping, or either while already braking as hard: the
  // deceleration in progress is at least as short.
  const bool harder = stop && c.end != motion_status_t::END_STOPPED;
  if (!c.halting || harder) {
    const double t = static_cast<double>(now_utime - c.start_utime) * 1e-6;
    const ScalarState state = MotionState(c.motion, t);
    const ScalarLimits& limits = stop ? c.motion.stop : c.motion.halt;
    JerkProfile decelerate = JerkProfile::StopFrom(state, limits.acceleration, limits.jerk);
    const ScalarState rest = decelerate.end();
    // Its own end is as near when the stop would reach the path's end; a
    // profile that would end moving backwards is never taken.
    if (rest.position < c.motion.path->length() && rest.velocity > -1e-9) {
      c.motion.timing = std::move(decelerate);
      c.start_utime = now_utime;
    }
    c.end = end;
    c.halting = true;
  }
  const double left = c.motion.duration_s() - static_cast<double>(now_utime - c.start_utime) * 1e-6;
  return Reply(r, ReplyCode::kDone, fmt::format("{}: at rest in {:.3f} s{}", what, left, queued), left);
}

motion_reply_t MotionService::DefineFrame(const motion_request_t& r) {
  if (Problem p = FrameDefinitionProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  frames_[r.frame] = WorkFrame{r.frame, TransformOf(Pose::FromVector(RequestPose(r)))};
  return Reply(r, ReplyCode::kDone, fmt::format("frame {} = {} in {{B}}", r.frame, PoseText(RequestPose(r))));
}

motion_reply_t MotionService::SetPivot(const motion_request_t& r) {
  if (Problem p = PivotProblem(r)) return Reply(r, ReplyCode::kInvalid, *p);
  const Vector3 c(r.point[0], r.point[1], r.point[2]);
  pivot_M_ = c;
  return Reply(
      r, ReplyCode::kDone,
      fmt::format("pivot ({:.6f}, {:.6f}, {:.6f}) m in {{M}}: moves from now turn about it", c(0), c(1), c(2)));
}

motion_reply_t MotionService::SetLimits(const motion_request_t& r) {
  MoveLimits l = default_limits_;
  if (Problem p = AllLimitsProblem(r, config_limits_, &l)) return Reply(r, ReplyCode::kInvalid, *p);
  default_limits_ = l;
  return Reply(r, ReplyCode::kDone,
               fmt::format("moves from now: {} m/s, {} rad/s, {} m/s^2, {} rad/s^2", l.speed_m_s, l.speed_rad_s,
                           l.accel_m_s2, l.accel_rad_s2));
}

void MotionService::OnLegState(const leg_state_t& legs, std::int64_t now_utime) {
  const std::lock_guard<std::mutex> lock(mutex_);
  leg_state_utime_ = now_utime;
  std::string holds;
  for (int i = 0; i < 6 && holds.empty(); ++i) {
    switch (legs.drive_status[i]) {
      case leg_state_t::DRIVE_ENABLED: break;
      case leg_state_t::DRIVE_HOLDING: holds = fmt::format("drive {} holding", i + 1); break;
      case leg_state_t::DRIVE_FAULT: holds = fmt::format("drive {} in fault", i + 1); break;
      default: holds = fmt::format("drive {} disabled", i + 1); break;
    }
  }
  if (holds.empty()) bridge_followed_ = true;
  if (holds.empty()) {
    holds_since_utime_ = 0;
  } else if (holds_since_utime_ == 0) {
    holds_since_utime_ = now_utime;
  }
  if (holds != bridge_holds_) Changed();
  bridge_holds_ = std::move(holds);
}

void MotionService::OnPlatformState(const platform_state_t& state, std::int64_t now_utime) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const bool was = OnTarget(now_utime);
  measured_utime_ = now_utime;
  for (int k = 0; k < 6; ++k) measured_pose_(k) = state.pose[k];
  measured_converged_ = state.fk_status == 0 && measured_pose_.allFinite();
  const MotionLimits& m = model_.config().motion;
  bool within = false;
  if (!Busy() && measured_converged_) {
    const auto [distance, angle] = PoseError(measured_pose_, hold_pose_, pivot_M_);
    within = distance <= m.on_target_tolerance_m && angle <= m.on_target_tolerance_rad;
  }
  if (!within)
    within_since_ = 0;
  else if (within_since_ == 0)
    within_since_ = now_utime;
  if (OnTarget(now_utime) != was) Changed();
}

bool MotionService::OnTarget(std::int64_t now_utime) const {
  if (Busy() || within_since_ == 0) return false;
  if (static_cast<double>(now_utime - measured_utime_) * 1e-6 > options_.measured_stale_s) return false;
  return static_cast<double>(now_utime - within_since_) * 1e-6 >= model_.config().motion.on_target_settle_s;
}

void MotionService::Finish(std::int64_t end_utime) {
  hold_pose_ = current_->motion.end_pose();
  last_end_ = current_->end;
  ended_utime_ = end_utime;
  current_.reset();
  within_since_ = 0;
  Changed();
}

void MotionService::Advance(std::int64_t now_utime) {
  if (!current_ && !queue_.empty()) {
    current_ = Running{std::move(queue_.front()), 0};
    queue_.pop_front();
  }
  while (current_) {
    if (current_->start_utime == 0) {
      current_->start_utime = now_utime;
      request_id_ = current_->motion.request_id;
      activity_ = current_->motion.activity;
      frame_ = current_->motion.frame;
      within_since_ = 0;
      Changed();
    }
    const std::int64_t end_utime = current_->start_utime + Micros(current_->motion.duration_s());
    if (now_utime < end_utime) return;
    Finish(end_utime);
    if (queue_.empty()) {
      StartFollowingIfEngaged(end_utime);
      return;
    }
    current_ = Running{std::move(queue_.front()), end_utime};  // from rest where the last one ended
    queue_.pop_front();
    request_id_ = current_->motion.request_id;
    activity_ = current_->motion.activity;
    frame_ = current_->motion.frame;
  }
}

pose_setpoint_t MotionService::Step(std::int64_t now_utime) {
  const std::lock_guard<std::mutex> lock(mutex_);
  Advance(now_utime);
  pose_setpoint_t sp{};
  sp.utime = now_utime;
  sp.seq = ++setpoint_seq_;
  sp.session_id = options_.session_id;
  PoseSample sample;
  sample.pose = hold_pose_;
  if (current_) {
    const double t = static_cast<double>(now_utime - current_->start_utime) * 1e-6;
    sample = SampleMotion(current_->motion, t);
    // Assigned, not built: the name's memory is reused cycle after cycle.
    const PathSegment segment = current_->motion.path->SegmentAt(MotionState(current_->motion, t).position);
    hold_name_ = segment.name != nullptr ? *segment.name : current_->motion.activity;
    hold_segment_ = segment.index;
    hold_phase_ = segment.dwells ? pose_setpoint_t::PHASE_DWELL : pose_setpoint_t::PHASE_MOVE;
  } else if (cueing_ && cueing_->following) {
    FollowCue(now_utime, &sample);
  }
  for (int k = 0; k < 6; ++k) {
    sp.pose[k] = sample.pose(k);
    sp.velocity[k] = sample.velocity(k);
    sp.acceleration[k] = sample.acceleration(k);
  }
  sp.trajectory = hold_name_;
  sp.segment = hold_segment_;
  sp.phase = hold_phase_;
  commanded_pose_ = sample.pose;
  return sp;
}

namespace {
// The bridge's stale limit: a hold shorter than this is the drives' own blip.
constexpr std::int64_t kTransientHoldUs = 50'000;
}  // namespace

std::int8_t MotionService::State(std::int64_t now_utime) const {
  // A drive holding for a cycle or two (its own watchdog, after a command
  // that came late on a stalled host) follows again by itself: the
  // status says fault once a hold has lasted the bridge's stale limit, as a
  // latched bridge's does, so a client waiting on a motion does not abort
  // it for a blip. A request meanwhile is still refused at once.
  const bool holds_for_now =
      !bridge_holds_.empty() && holds_since_utime_ != 0 && now_utime - holds_since_utime_ < kTransientHoldUs;
  if (bridge_followed_ && !holds_for_now && BridgeProblem(now_utime)) return motion_status_t::STATE_FAULT;
  if (current_) return current_->halting ? motion_status_t::STATE_HALTING : motion_status_t::STATE_MOVING;
  if (!queue_.empty()) return motion_status_t::STATE_MOVING;
  if (cueing_ && cueing_->following) return motion_status_t::STATE_CUEING;
  if (refused_) return motion_status_t::STATE_REFUSED;
  return ever_moved_ ? motion_status_t::STATE_HOLDING : motion_status_t::STATE_IDLE;
}

motion_status_t MotionService::Status(std::int64_t now_utime) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  motion_status_t s{};
  s.utime = now_utime;
  s.session_id = options_.session_id;
  s.state = State(now_utime);
  s.request_id = request_id_;
  s.activity = current_ ? current_->motion.activity : activity_;
  if (current_ && current_->start_utime != 0) {
    const double d = current_->motion.duration_s();
    s.progress =
        d > 0.0 ? std::clamp(static_cast<double>(now_utime - current_->start_utime) * 1e-6 / d, 0.0, 1.0) : 1.0;
  } else {
    s.progress = last_end_ == motion_status_t::END_COMPLETED && !current_ ? 1.0 : 0.0;
  }
  s.queued = static_cast<std::int32_t>(queue_.size());
  s.last_end = last_end_;
  const Vector6 target = current_ ? current_->motion.end_pose() : hold_pose_;
  for (int k = 0; k < 6; ++k) {
    s.pose_commanded[k] = commanded_pose_(k);
    s.pose_target[k] = target(k);
    s.pose_measured[k] = measured_pose_(k);
  }
  s.measured_valid =
      measured_converged_ && static_cast<double>(now_utime - measured_utime_) * 1e-6 <= options_.measured_stale_s;
  s.on_target = OnTarget(now_utime);
  s.frame = frame_;
  const WorkFrame* frame = FindFrame(frame_);
  const Vector6 frame_pose = frame ? PoseOf(frame->X_BW).ToVector() : Vector6::Zero();
  for (int k = 0; k < 6; ++k) s.frame_pose[k] = frame_pose(k);
  for (int k = 0; k < 3; ++k) s.pivot[k] = pivot_M_(k);
  if (s.state == motion_status_t::STATE_FAULT)
    s.reason = BridgeProblem(now_utime).value_or("");
  else if (s.state == motion_status_t::STATE_REFUSED)
    s.reason = *refused_;
  return s;
}

bool MotionService::busy() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return Busy();
}

std::int64_t MotionService::ended_utime() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return ended_utime_;
}

bool MotionService::TakeChange() {
  const std::lock_guard<std::mutex> lock(mutex_);
  const bool changed = changed_;
  changed_ = false;
  return changed;
}

}  // namespace edsp
