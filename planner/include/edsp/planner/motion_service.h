#pragma once
// The planner's motion service, free of any bus: requests in
// (EDSP_MOTION_REQUEST), a reply to each, a setpoint per cycle and the
// motion status out. Moves run one after another (a move asked for while
// another runs is queued behind it: it starts from rest where the one
// before ends, so no velocity steps); halt and stop decelerate the motion
// in progress along its own path and cancel the queue. Every path is
// checked whole before its first setpoint. docs/operating.md.
//
// A cueing source (edsp-cueing, docs/cueing.md) is one more motion: an
// engage request moves to its neutral pose by a checked move, and from the
// move's end the setpoints follow the source's (EDSP_CUE_SETPOINT) while
// each is valid: this session's, finite, inside the workspace, no leg
// faster than the config allows since the last one followed, and fresh.
// The first that is not ends the cueing where the platform stands: it
// holds the last valid pose and the status says why. Disengage leaves the
// cueing and moves to the pose asked for; halt and stop end it at once.
//
// Thread-safe: the planner's cycle (Step) runs on one thread while moves
// are planned on another, the lock released while a path is checked (a
// long program takes tens of milliseconds), so setpoints never wait for a
// plan. A halt or stop that comes meanwhile wins: the plan is refused.

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <memory>
#include <optional>
#include <string>

#include "edsp/kinematics/platform_model.h"
#include "edsp/leg_state_t.hpp"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/request_service.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/planner/motion_request_checks.h"
#include "edsp/planner/planned_motion.h"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

using ProgramLibrary = std::function<std::unique_ptr<TrajectorySequence>(const std::string& motions)>;

struct MotionServiceOptions {
  std::int64_t session_id = 0;
  double request_window_s = 5.0;  // a request stamped further from this clock is refused (replayed, or a clock off)
  double bridge_stale_s = 0.5;    // no leg state this long: the bridge is not following
  double measured_stale_s = 0.5;  // no platform state this long: no measured pose
  std::size_t queue_max = 64;
  double check_rate_hz = 1000.0;  // the planner's cycle: every path is checked at it
  // The programs a run request names, as a list ("Lz,Lx", "calibration"),
  // planned one after another from home; throws std::invalid_argument naming
  // an unknown one. Unset: the paper's motions with their default options
  // (edsp-planner gives the whole motion library, motion_library.h).
  ProgramLibrary programs;
  double cue_stale_s = 0.02;  // while cueing: no valid EDSP_CUE_SETPOINT this long ends it (the source is gone)
};

// A cueing source the motion service has engaged (at namespace scope: a
// nested class with default member initializers is not yet default
// constructible inside its enclosing class for clang's std::optional).
struct EngagedCueing {
  std::string source;  // the client that engaged it
  std::int64_t request_id = 0;
  bool following = false;                 // the engage move has ended: the setpoints are the source's
  std::int64_t following_utime = 0;       // since when
  std::optional<pose_setpoint_t> latest;  // its last setpoint that was valid on its own
  std::int64_t latest_utime = 0;          // when that came, on this service's clock
  std::int64_t followed_utime = 0;        // the last cycle that followed one (0: none yet)
};

class MotionService {
 public:
  MotionService(const PlatformModel& model, MotionServiceOptions options);

  // Plays `program` from home at once (edsp-planner --motions/--csv) and
  // serves requests beside it. Throws std::invalid_argument naming the
  // first violation if its path cannot be followed.
  void StartProgram(std::unique_ptr<TrajectorySequence> program, const std::string& name);

  motion_reply_t Handle(const motion_request_t& request, std::int64_t now_utime);
  // Requests answered at once, without planning a path (request_kinds.h's
  // plans_path false, and kinds it does not know): the loop handles them on
  // its own thread.
  static bool IsQuick(const motion_request_t& request);
  void OnLegState(const leg_state_t& legs, std::int64_t now_utime);
  void OnPlatformState(const platform_state_t& state, std::int64_t now_utime);
  // A cueing source's setpoint: kept while cueing is engaged, followed from
  // the engage move's end (ignored while nothing is engaged).
  void OnCueSetpoint(const pose_setpoint_t& cue, std::int64_t now_utime);

  // The setpoint for `now` (advances the motion; call once per cycle).
  pose_setpoint_t Step(std::int64_t now_utime);
  motion_status_t Status(std::int64_t now_utime) const;
  // True once after each change of state, request or end (publish the status at once).
  bool TakeChange();
  // Why the last cueing ended on a cue it could not follow, once (the loop's EDSP_FAULT).
  struct CueFault {
    FaultCode code;
    std::string reason;
  };
  std::optional<CueFault> TakeCueFault();

  bool busy() const;
  // The time the last motion ended (0: none has).
  std::int64_t ended_utime() const;

 private:
  struct Running {
    PlannedMotion motion;
    std::int64_t start_utime = 0;  // 0: at the next Step
    bool halting = false;
    std::int8_t end = motion_status_t::END_COMPLETED;
  };

  using Lock = std::unique_lock<std::mutex>;

  motion_reply_t Act(const motion_request_t& r, std::int64_t now_utime, Lock& lock);
  motion_reply_t Reply(const motion_request_t& r, ReplyCode code, std::string reason, double duration_s = 0.0,
                       double start_delay_s = 0.0) const;
  motion_reply_t Move(const motion_request_t& r, bool check_only, std::int64_t now_utime, Lock& lock);
  // A move relative to the last target by one small step along one axis (JogProblem).
  motion_reply_t Jog(const motion_request_t& r, std::int64_t now_utime, Lock& lock);
  motion_reply_t Run(const motion_request_t& r, std::int64_t now_utime, Lock& lock);
  motion_reply_t Decelerate(const motion_request_t& r, bool stop, std::int64_t now_utime);
  motion_reply_t DefineFrame(const motion_request_t& r);
  motion_reply_t SetPivot(const motion_request_t& r);
  motion_reply_t SetLimits(const motion_request_t& r);
  motion_reply_t Engage(const motion_request_t& r, std::int64_t now_utime, Lock& lock);
  motion_reply_t Disengage(const motion_request_t& r, std::int64_t now_utime, Lock& lock);
  // Why a cue setpoint cannot be followed on its own (nothing if it can).
  Problem CueProblem(const pose_setpoint_t& cue, std::int64_t now_utime, FaultCode* code) const;
  // The setpoint `to` the latest cue gives at `now`, unless the cueing must end: then why.
  Problem CueToFollow(std::int64_t now_utime, FaultCode* code, PoseSample* to) const;
  // The largest leg move between two poses, and what the legs may go in `span_s`.
  struct LegStep {
    double most_m = 0.0, allowed_m = 0.0;
    int leg = 0;
  };
  LegStep LegStepBetween(const Vector6& from, const Vector6& to, double span_s) const;
  // Ends the cueing where the platform stands; a `fault` ended it: its reason
  // is the status's (a refusal) and it is raised once (TakeCueFault).
  void EndCueing(std::int64_t now_utime, std::int8_t end, std::optional<CueFault> fault = std::nullopt);
  Problem CueingProblem() const;  // why a move or run must wait (nothing if nothing is engaged)
  void StartCueing(const std::string& source, std::int64_t request_id);  // engaged, not yet following
  // After a motion ends: an engage move's end starts the following.
  void StartFollowingIfEngaged(std::int64_t now_utime);
  // This cycle's setpoint from the latest cue into `sample`, or the cueing ended.
  void FollowCue(std::int64_t now_utime, PoseSample* sample);
  motion_reply_t Enqueue(const motion_request_t& r, std::deque<PlannedMotion> motions, std::int64_t now_utime);

  Problem BridgeProblem(std::int64_t now_utime) const;
  const WorkFrame* FindFrame(const std::string& name) const;
  Transform PlannedEnd() const;
  double TimeToIdle(std::int64_t now_utime) const;
  void Advance(std::int64_t now_utime);
  void Finish(std::int64_t end_utime);
  std::int8_t State(std::int64_t now_utime) const;
  bool OnTarget(std::int64_t now_utime) const;
  void Changed() { changed_ = true; }
  bool Busy() const { return current_.has_value() || !queue_.empty() || cueing_.has_value(); }
  Problem QueueProblem() const;
  // Why a plan made from `from` before `decelerations` halts may not be queued (nothing if it may).
  Problem PlanOutdated(const Transform& from, std::uint64_t decelerations) const;

  mutable std::mutex mutex_;
  PlatformModel model_;
  MotionServiceOptions options_;
  MoveLimits config_limits_, default_limits_;
  std::map<std::string, WorkFrame> frames_;
  Vector3 pivot_M_ = Vector3::Zero();

  std::optional<Running> current_;
  std::deque<PlannedMotion> queue_;
  Vector6 hold_pose_;            // where the platform holds when nothing runs
  Vector6 commanded_pose_;       // the last setpoint's
  std::int64_t request_id_ = 0;  // the motion in progress or the last one
  std::string activity_ = "hold";
  std::string hold_name_ = "hold";  // the setpoints' trajectory name: the last motion's while holding
  std::int32_t hold_segment_ = 0;
  std::int8_t hold_phase_ = pose_setpoint_t::PHASE_HOLD;
  std::string frame_ = "base";
  std::int8_t last_end_ = motion_status_t::END_NONE;
  std::int64_t ended_utime_ = 0;
  bool ever_moved_ = false;
  std::optional<std::string> refused_;  // the last request's refusal, until one is accepted
  bool changed_ = true;
  std::uint64_t decelerations_ = 0;  // halts and stops so far: a plan older than the last is refused
  std::int64_t setpoint_seq_ = 0;
  std::optional<EngagedCueing> cueing_;
  std::optional<CueFault> cue_fault_;

  RequestService<motion_reply_t> requests_{RequestPolicy{options_.session_id, options_.request_window_s}};

  std::int64_t leg_state_utime_ = 0;
  std::string bridge_holds_;            // "" while every drive follows
  std::int64_t holds_since_utime_ = 0;  // when the drives began to hold (0: they follow)
  bool bridge_followed_ = false;        // seen following once
  std::int64_t measured_utime_ = 0;
  Vector6 measured_pose_ = Vector6::Zero();
  bool measured_converged_ = false;
  std::int64_t within_since_ = 0;  // measured within tolerance of the target since (0: not)
};

}  // namespace edsp
