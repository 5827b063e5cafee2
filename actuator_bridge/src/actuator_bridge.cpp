#include "edsp/actuator_bridge/actuator_bridge.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/node/fault.h"
#include "edsp/node/stamp_check.h"

namespace edsp {
namespace {

// FaultThrottle's interval: a second fault of the same channel and code
// sooner would be swallowed, though marked reported here.
constexpr std::int64_t kNewReasonSpacingUs = 100000;

// A leg state is stamped with the instant its reading describes, as every
// message is (the rig's image latched it at its cycle's start, most of a
// cycle before this read): paired with the tracker sample of that instant
// by its stamp, not with one a cycle later, whose legs had moved on (0.25 mm
// at 0.25 m/s). A reading the drives do not date, or older than two cycles
// (drives that stopped publishing), is stamped with the read.
std::int64_t DescribedInstant(const DriveFeedback& feedback, std::int64_t now_utime) {
  constexpr std::int64_t kFreshestUs = 2000;
  const bool dated = feedback.utime > 0 && feedback.utime <= now_utime && now_utime - feedback.utime <= kFreshestUs;
  return dated ? feedback.utime : now_utime;
}

}  // namespace

ActuatorBridge::ActuatorBridge(PlatformModel model, DriveBackend* backend, BridgeOptions options)
    : model_(std::move(model)), backend_(backend), options_(std::move(options)) {
  if (options_.max_leg_speed_m_s < 0.0) options_.max_leg_speed_m_s = model_.config().limits.leg_speed_max_m_s;
  if (options_.stop_decel_m_s2 < 0.0) options_.stop_decel_m_s2 = model_.config().motion.leg_accel_max_m_s2;
  ride_.continue_s = timing::kRideThroughS;
  // Hold wherever the drives are now.
  backend_->Read(0, &feedback_);
  for (int i = 0; i < kNumLegs; ++i) {
    target_.motor_angle_rad[i] = feedback_.motor_angle_rad[i];
    target_length_m_(i) = model_.LengthFromMotorAngle(i, feedback_.motor_angle_rad[i]);
  }
  stream_length_m_ = target_length_m_;
}

fault_t ActuatorBridge::Fault(FaultCode code, std::string reason, std::int64_t now_utime) const {
  return MakeFault(options_.node_name, channel::kLegCommand, code, fault_t::SEVERITY_ERROR, std::move(reason),
                   now_utime);
}

bool ActuatorBridge::Reject(FaultCode code, std::string reason, std::int64_t now_utime, fault_t* fault) {
  ++rejected_;
  *fault = Fault(code, std::move(reason), now_utime);
  return false;
}

void ActuatorBridge::Apply(BridgeEvent event) {
  const BridgeTransition t = NextBridgeState(state_, event);
  const BridgeState next = t.allowed ? t.next : BridgeState::kLatched;
  if (next == BridgeState::kLatched && state_ != BridgeState::kLatched) {
    latch_cause_ = !t.allowed                          ? "an unexpected event"
                   : event == BridgeEvent::kDrivesLost ? "a drive outage"
                                                       : "stale input";
  }
  state_ = next;
}

bool ActuatorBridge::Rearm(std::string* error) {
  // Latched after a fault, or holding since start-up while the stream it was
  // started into refuses as a jump (a restarted bridge): rejoin it.
  if (Moving()) return true;
  std::string why;
  // A backend in fault before any cycle saw it (a drive found faulted at
  // start-up) is reset too.
  const bool needs_reset = !backend_ok_ || backend_->state() == BackendState::kFault;
  if (needs_reset && !backend_->Reset(&why)) {
    if (error != nullptr) *error = why;
    return false;
  }
  Apply(BridgeEvent::kRearm);
  return true;
}

RequestService<reply_t>::Answer ActuatorBridge::HandleArm(const arm_t& arm, std::int64_t now_utime) {
  return arm_requests_.Handle(
      arm, now_utime, [&](ReplyCode code, std::string reason) { return ArmReply(code, "re-arm " + reason); },
      [&] { return ActOnArm(arm); });
}

reply_t ActuatorBridge::ArmReply(ReplyCode code, std::string reason) const {
  reply_t reply{};
  reply.node = options_.node_name;
  reply.request_channel = channel::kArm;
  reply.code = static_cast<std::int8_t>(code);
  reply.reason = std::move(reason);
  return reply;
}

reply_t ActuatorBridge::ActOnArm(const arm_t& arm) {
  const bool was_latched = latched();
  std::string error;
  if (!Rearm(&error)) {
    return ArmReply(ReplyCode::kFailed,
                    fmt::format("re-arm by {} failed: the drives cannot be enabled: {}", arm.operator_name, error));
  }
  return ArmReply(
      ReplyCode::kDone,
      fmt::format("re-armed by {}{}", arm.operator_name,
                  was_latched ? fmt::format("; rejoining the command stream at {:.3f} m/s", options_.rejoin_speed_m_s)
                              : std::string(" (was not latched)")));
}

Vector6 ActuatorBridge::NextTarget(const Vector6& command_m, const Vector6& stream_motion_m, double max_step_m,
                                   double elapsed_s, bool* caught_up) const {
  *caught_up = false;
  if (!IsRejoining(state_)) return command_m;
  // Towards the command along the straight line in leg space (between two
  // checked points: within the strokes), far enough that the gap the last
  // step left to the stream shrinks by the rejoin step: a stream moving
  // away is gone after as it moves, so one faster than the rejoin speed is
  // still caught; never less than the rejoin step, never past the legs'.
  const Vector6 gap = command_m - target_length_m_;
  const double largest = gap.cwiseAbs().maxCoeff();
  const double rejoin_step_m = options_.rejoin_speed_m_s * elapsed_s;
  const double left_before = (gap - stream_motion_m).cwiseAbs().maxCoeff();
  const double step = std::min(max_step_m, std::max(rejoin_step_m, largest - (left_before - rejoin_step_m)));
  if (largest <= step) {
    *caught_up = true;  // the stream again
    return command_m;
  }
  return target_length_m_ + gap * (step / largest);
}

bool ActuatorBridge::HandleCommand(const leg_command_t& c, std::int64_t now_utime, fault_t* fault) {
  if (std::optional<Refusal> refusal = WhyNotListening(c, now_utime)) {
    return Reject(refusal->code, std::move(refusal->reason), now_utime, fault);
  }
  const StepLimit step = StepLimitFor(c);
  Vector6 command_m;
  if (std::optional<Refusal> refusal = WhyNotTheseLengths(c, step, &command_m)) {
    return Reject(refusal->code, std::move(refusal->reason), now_utime, fault);
  }
  Accept(c, command_m, CatchAStreamThatWentOn(command_m, step, now_utime), now_utime);
  return true;  // to the drives at the next cycle's write
}

ActuatorBridge::StepLimit ActuatorBridge::CatchAStreamThatWentOn(const Vector6& command_m, const StepLimit& step,
                                                                 std::int64_t now_utime) {
  // Only a stream back after a silence, to drives that say they stood on
  // their own watchdog meanwhile (drives that went on, or were bridged over
  // the pause by whoever drives them, follow it as they always do).
  if (!Moving() || SinceLastCommandUs(now_utime) <= timing::kFeedForwardLapseUs) return step;
  const bool stood = std::any_of(feedback_.status.begin(), feedback_.status.end(),
                                 [](DriveStatus s) { return s == DriveStatus::kHolding; });
  if (!stood) return step;
  Vector6 drives_m;
  for (int i = 0; i < kNumLegs; ++i) drives_m(i) = model_.LengthFromMotorAngle(i, feedback_.motor_angle_rad[i]);
  const double one_cycle_m = options_.max_leg_speed_m_s * static_cast<double>(timing::kCycleUs) * 1e-6;
  if ((command_m - drives_m).cwiseAbs().maxCoeff() <= one_cycle_m) return step;
  // Farther than the legs go in a cycle: a step there would be caught by
  // the servo faster than the legs may go. Rejoin it from where the drives
  // stand, a rejoin step a cycle.
  Apply(BridgeEvent::kStreamAhead);
  // Where the stream went during the silence is the gap to close, not a
  // motion of the stream's to carry the legs along.
  stream_length_m_ = command_m;
  for (int i = 0; i < kNumLegs; ++i) {
    target_.motor_angle_rad[i] = feedback_.motor_angle_rad[i];
    target_length_m_(i) = drives_m(i);
  }
  StepLimit from_the_drives = step;
  from_the_drives.elapsed_s = static_cast<double>(timing::kCycleUs) * 1e-6;
  return from_the_drives;
}

std::optional<ActuatorBridge::Refusal> ActuatorBridge::WhyNotListening(const leg_command_t& c, std::int64_t now_utime) {
  if (state_ == BridgeState::kLatched) {
    return Refusal{FaultCode::kLatched, fmt::format("leg command seq {} refused: holding after {} since command "
                                                    "seq {}; re-arm required (EDSP_ARM)",
                                                    c.seq, latch_cause_, last_command_seq_)};
  }
  if (Moving() && SinceLastCommandUs(now_utime) > options_.stale_us) {
    // Starved longer than the stale limit and no cycle noticed (this process
    // was frozen, or descheduled): whatever comes now may be anywhere. Hold
    // first, as a cycle would have.
    // Its drives were left alone as long: they stopped on their own
    // watchdog. Hold them there (writing the last command would pull them
    // back by up to the drives' interpolation horizon).
    const std::int64_t silent_us = SinceLastCommandUs(now_utime);
    Apply(BridgeEvent::kStale);
    HoldAtRest(now_utime);
    hold_where_the_drives_are_ = true;  // at the next cycle's read
    return Refusal{FaultCode::kLatched,
                   fmt::format("leg command seq {} refused: no valid leg command for {} us before it "
                               "(limit {} us); holding the last valid position (command seq {}) until "
                               "re-armed",
                               c.seq, silent_us, options_.stale_us, last_command_seq_)};
  }
  if (hold_where_the_drives_are_) {
    // Frozen, then re-armed before a cycle read where the drives' watchdog
    // stopped them: a stream started now would rejoin from the last command
    // and pull them back. The next cycle reads them (1 ms).
    return Refusal{FaultCode::kStale, fmt::format("leg command seq {} refused: where the drives stopped during this "
                                                  "bridge's freeze is not read yet (next cycle)",
                                                  c.seq)};
  }
  if (!backend_ok_) {
    return Refusal{FaultCode::kBackend, fmt::format("leg command seq {} refused: the drives do not answer", c.seq)};
  }
  if (c.session_id != options_.session_id) {
    return Refusal{FaultCode::kForeignSession,
                   fmt::format("leg command seq {} from session {}, this group is session {}", c.seq, c.session_id,
                               options_.session_id)};
  }
  std::optional<std::string> stamp =
      StampProblem(fmt::format("leg command seq {}", c.seq), c.utime, now_utime, options_.stale_us);
  if (stamp) return Refusal{FaultCode::kStale, std::move(*stamp)};
  return std::nullopt;
}

// A step longer than the legs could travel at full speed in the planner
// time between the two setpoints is a jump. Planner time, not arrival time:
// a late cycle or a burst of queued commands is not motion. After a hold
// (or at start) only a one-cycle step continues from the held position.
ActuatorBridge::StepLimit ActuatorBridge::StepLimitFor(const leg_command_t& c) const {
  StepLimit step;
  step.basis_utime = c.setpoint_utime != 0 ? c.setpoint_utime : c.utime;
  step.elapsed_s = 1e-3;
  step.since_s = 1e-3;
  if (Moving()) {
    // In double: setpoint_utime is the sender's word, and any int64 may come.
    const double since_s = (static_cast<double>(step.basis_utime) - static_cast<double>(last_basis_utime_)) * 1e-6;
    step.elapsed_s = std::clamp(since_s, 1e-3, static_cast<double>(options_.stale_us) * 1e-6);
    step.since_s = std::min(since_s, step.elapsed_s);
  }
  step.max_step_m = options_.max_leg_speed_m_s * step.elapsed_s + 1e-6;
  return step;
}

std::optional<ActuatorBridge::Refusal> ActuatorBridge::WhyNotTheseLengths(const leg_command_t& c, const StepLimit& step,
                                                                          Vector6* command_m) const {
  const WorkspaceLimits& limits = model_.config().limits;
  // Rejoining: the first command after the re-arm starts the stream anew;
  // the ones after it must continue from it.
  const bool stream_starts = state_ == BridgeState::kArmed;
  const Vector6& reference = IsRejoining(state_) ? stream_length_m_ : target_length_m_;
  for (int i = 0; i < kNumLegs; ++i) {
    const double length = c.command_length_m[i];
    if (!std::isfinite(length)) {
      return Refusal{FaultCode::kNonFinite,
                     fmt::format("leg command seq {}: leg {} length is not finite", c.seq, i + 1)};
    }
    if (length < limits.leg_min_m || length > limits.leg_max_m) {
      return Refusal{FaultCode::kOutOfStroke,
                     fmt::format("leg command seq {}: leg {} length {:.6f} m outside {:.3f}..{:.3f} m", c.seq, i + 1,
                                 length, limits.leg_min_m, limits.leg_max_m)};
    }
    if (!stream_starts && std::abs(length - reference(i)) > step.max_step_m) {
      return Refusal{FaultCode::kJump,
                     fmt::format("leg command seq {}: leg {} jumps {:.6f} m from the {} {:.6f} m "
                                 "(at most {:.6f} m in {:.1f} ms)",
                                 c.seq, i + 1, length - reference(i), IsRejoining(state_) ? "previous command" : "held",
                                 reference(i), step.max_step_m, step.elapsed_s * 1e3)};
    }
    (*command_m)(i) = length;
  }
  return std::nullopt;
}

void ActuatorBridge::Accept(const leg_command_t& c, const Vector6& command_m, const StepLimit& step,
                            std::int64_t now_utime) {
  // A stream that starts now (re-armed) has no motion of its own yet.
  const Vector6 stream_motion_m =
      state_ == BridgeState::kArmed ? Vector6::Zero().eval() : (command_m - stream_length_m_).eval();
  stream_length_m_ = command_m;
  bool caught_up = false;
  const bool rejoining = IsRejoining(state_);
  const Vector6 next = NextTarget(command_m, stream_motion_m, step.max_step_m, step.elapsed_s, &caught_up);
  Apply(BridgeEvent::kCommandAccepted);
  if (caught_up) Apply(BridgeEvent::kCaughtUp);
  // The feed-forward over the planner time the step took: a setpoint 0.3 ms
  // after a late one moved 0.3 ms worth, and over a whole cycle it was a
  // third of the speed, a kick the servo turned into ±0.4 mm at 0.25 m/s
  // (docs/calibration.md). Stamps closer than kShortestFeedForwardBasisS (a
  // repeated or reordered setpoint) keep the last feed-forward. A rejoin's
  // step (and its last, the rest of the gap) is over the clamped time, and
  // so is its velocity; so is a step the jump check let
  // through that the time since the last setpoint does not explain (faster
  // than the legs go), which over that time would be a kick of its own.
  const bool explained =
      (next - target_length_m_).cwiseAbs().maxCoeff() <= options_.max_leg_speed_m_s * step.since_s + 1e-6;
  const double basis_s = rejoining || !explained ? step.elapsed_s : step.since_s;
  const bool resolvable = basis_s >= kShortestFeedForwardBasisS;
  for (int i = 0; i < kNumLegs; ++i) {
    const double angle = model_.MotorAngleFromLength(i, next(i));
    if (!target_utime_)
      target_.motor_velocity_rad_s[i] = 0.0;
    else if (resolvable)
      target_.motor_velocity_rad_s[i] = (angle - target_.motor_angle_rad[i]) / basis_s;
    target_.motor_angle_rad[i] = angle;
    target_length_m_(i) = next(i);
  }
  target_.utime = step.basis_utime;
  target_utime_ = now_utime;
  paused_since_command_ = false;
  written_since_command_.reset();
  ride_.stop_s = StopTimeS(target_, model_.LengthFromMotorAngle(0, 1.0) - model_.LengthFromMotorAngle(0, 0.0),
                           options_.stop_decel_m_s2);
  last_basis_utime_ = step.basis_utime;
  last_command_seq_ = c.seq;
  ++accepted_;
}

bool ActuatorBridge::LoseDrives(std::int64_t now_utime, fault_t* fault) {
  // Drives that do not answer may not have followed: nothing the stream
  // says next can be checked against where they are. Hold and latch.
  const bool was_moving = Moving();
  Apply(BridgeEvent::kDrivesLost);
  HoldAtRest(now_utime);
  const std::string detail = backend_->Detail();
  reported_reasons_ = {detail};
  backend_report_utime_ = now_utime;
  *fault = Fault(FaultCode::kBackend,
                 fmt::format("drive backend failed a cycle (drives silent or not active){}{}",
                             detail.empty() ? std::string() : " [" + detail + "]",
                             was_moving ? fmt::format(": holding the last valid position (command "
                                                      "seq {}) until re-armed",
                                                      last_command_seq_)
                                        : std::string()),
                 now_utime);
  return true;
}

bool ActuatorBridge::ReportNewReason(std::int64_t now_utime, fault_t* fault) {
  const std::string detail = backend_->Detail();
  if (detail.empty() || reported_reasons_.count(detail) > 0 ||
      now_utime - backend_report_utime_ < kNewReasonSpacingUs) {
    return false;
  }
  reported_reasons_.insert(detail);
  backend_report_utime_ = now_utime;
  *fault = Fault(FaultCode::kBackend,
                 fmt::format("drive backend still failing [{}]: holding until it answers and is re-armed", detail),
                 now_utime);
  return true;
}

void ActuatorBridge::NoteOwnPause(std::int64_t now_utime) {
  // Longer between two of its cycles than the drives continue a setpoint:
  // this bridge paused (the whole host descheduled, most often, its planner
  // with it). Its drives went on by themselves meanwhile, and the rig
  // emulator bridges such a pause to the next command; a motion continued
  // by the bridge now, stamped after the pause, would be taken for one.
  if (last_cycle_utime_ >= 0 && now_utime - last_cycle_utime_ > timing::kFeedForwardLapseUs)
    paused_since_command_ = true;
}

DriveSetpoint ActuatorBridge::SetpointNow(std::int64_t now_utime) const {
  return Moving() ? RiddenThrough(now_utime) : target_;
}

DriveSetpoint ActuatorBridge::RiddenThrough(std::int64_t now_utime) const {
  const std::int64_t silent_us = SinceLastCommandUs(now_utime);
  if (target_.utime == 0 || silent_us <= timing::kFeedForwardLapseUs) return target_;
  // After a pause of its own, what the drives were last told, under its own
  // stamp, feed-forward and all: they continued it from that instant as far
  // as they do, and a copy is not a new command to them. (A copy with the
  // feed-forward dropped would be one: the emulator's drives would go back
  // to the command's place after pauses of the whole host; and the command
  // itself, once its motion was ridden through, pulled them back as far.)
  if (paused_since_command_) return written_since_command_.value_or(target_);
  DriveSetpoint ridden = RideThroughSetpoint(target_, ride_, static_cast<double>(silent_us) * 1e-6);
  KeepWithinStroke(&ridden);
  return ridden;
}

std::array<double, 6> ActuatorBridge::RestAngles(std::int64_t now_utime) const {
  if (!paused_since_command_) return RiddenThrough(now_utime).motor_angle_rad;  // the rest of the ramp is the servo's
  const DriveSetpoint last = written_since_command_.value_or(target_);
  const bool at_rest = std::all_of(last.motor_velocity_rad_s.begin(), last.motor_velocity_rad_s.end(),
                                   [](double v) { return v == 0.0; });
  // A setpoint still moving: the drives went on along it by themselves and
  // stopped on their own watchdog, wherever their reading now says.
  return at_rest ? last.motor_angle_rad : feedback_.motor_angle_rad;
}

void ActuatorBridge::KeepWithinStroke(DriveSetpoint* setpoint) const {
  // The bridge's own setpoints are checked as a command is: a leg the
  // continued motion would take past its stroke stops at its end.
  const WorkspaceLimits& limits = model_.config().limits;
  for (int i = 0; i < kNumLegs; ++i) {
    const double length = model_.LengthFromMotorAngle(i, setpoint->motor_angle_rad[i]);
    const double within = std::clamp(length, limits.leg_min_m, limits.leg_max_m);
    if (within == length) continue;
    setpoint->motor_angle_rad[i] = model_.MotorAngleFromLength(i, within);
    setpoint->motor_velocity_rad_s[i] = 0.0;
  }
}

void ActuatorBridge::HoldAtRest(std::int64_t now_utime) {
  // Where the late command's motion comes to rest, never back at the command.
  const std::array<double, 6> rest = RestAngles(now_utime);
  for (int i = 0; i < kNumLegs; ++i) {
    target_.motor_angle_rad[i] = rest[i];
    target_length_m_(i) = model_.LengthFromMotorAngle(i, rest[i]);
  }
  target_.motor_velocity_rad_s.fill(0.0);
  target_.utime = 0;
}

void ActuatorBridge::HoldWhereTheDrivesAre() {
  for (int i = 0; i < kNumLegs; ++i) {
    target_.motor_angle_rad[i] = feedback_.motor_angle_rad[i];
    target_.motor_velocity_rad_s[i] = 0.0;
    target_length_m_(i) = model_.LengthFromMotorAngle(i, feedback_.motor_angle_rad[i]);
  }
  target_.utime = 0;
  stream_length_m_ = target_length_m_;
}

bool ActuatorBridge::Cycle(std::int64_t now_utime, leg_state_t* state, fault_t* fault) {
  bool raised = false;
  // The read phase: where the drives are at the cycle's start.
  // This bridge not cycling for longer than the stale limit (frozen,
  // descheduled): the drives stopped on their own watchdog, wherever that
  // was; hold them there rather than pull them back to the last command.
  const bool self_starved = last_cycle_utime_ >= 0 && now_utime - last_cycle_utime_ > options_.stale_us;
  NoteOwnPause(now_utime);
  last_cycle_utime_ = now_utime;
  const bool read_ok = backend_->Read(now_utime, &feedback_);
  if (Moving() && SinceLastCommandUs(now_utime) > options_.stale_us) {
    Apply(BridgeEvent::kStale);
    HoldAtRest(now_utime);
    *fault = Fault(FaultCode::kLatched,
                   fmt::format("no valid leg command for {} us: holding the last valid "
                               "position (command seq {}) until re-armed",
                               SinceLastCommandUs(now_utime), last_command_seq_),
                   now_utime);
    raised = true;
  }
  // Drives that answer again after an outage are held where they are now (a
  // restarted rig, or drives that moved while unobserved), not driven back
  // to a target from before it.
  if (read_ok && !Moving() && (!backend_ok_ || self_starved || hold_where_the_drives_are_)) {
    HoldWhereTheDrivesAre();
    hold_where_the_drives_are_ = false;
  }
  if (!read_ok && backend_ok_) raised = LoseDrives(now_utime, fault);  // this cycle writes at rest
  // The write phase: the cycle's one setpoint.
  const DriveSetpoint setpoint = SetpointNow(now_utime);
  const bool write_ok = backend_->Write(now_utime, setpoint);
  if (Moving()) written_since_command_ = setpoint;
  if (read_ok && !write_ok && backend_ok_) raised = LoseDrives(now_utime, fault);  // at rest from the next write
  const bool backend_ok = read_ok && write_ok;
  if (backend_ok && !backend_ok_ && !raised) {
    *fault = Fault(FaultCode::kBackend,
                   latched() ? "drive backend answers again; holding until re-armed" : "drive backend answers again",
                   now_utime);
    fault->severity = fault_t::SEVERITY_INFO;
    raised = true;
  }
  if (!backend_ok && !backend_ok_ && !raised) raised = ReportNewReason(now_utime, fault);
  backend_ok_ = backend_ok;
  *state = leg_state_t{};
  state->utime = DescribedInstant(feedback_, now_utime);
  state->seq = ++state_seq_;
  state->command_seq = last_command_seq_;
  for (int i = 0; i < kNumLegs; ++i) {
    state->motor_angle_rad[i] = feedback_.motor_angle_rad[i];
    state->motor_velocity_rad_s[i] = feedback_.motor_velocity_rad_s[i];
    state->encoder_length_m[i] = model_.LengthFromMotorAngle(i, feedback_.motor_angle_rad[i]);
    state->drive_status[i] = !Moving() && feedback_.status[i] == DriveStatus::kEnabled
                                 ? leg_state_t::DRIVE_HOLDING
                                 : static_cast<std::int8_t>(feedback_.status[i]);
  }
  return raised;
}

}  // namespace edsp
