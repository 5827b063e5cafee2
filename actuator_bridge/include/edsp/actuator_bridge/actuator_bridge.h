#pragma once
// The actuator bridge's logic, free of any bus: leg commands in, drive
// setpoints out, encoders back as leg states. Safety first: it forwards only
// commands it can validate (session, finite, within stroke, no jump from the
// last valid target), and when commands stop coming (stale) it holds the last
// valid position and stays latched there until explicitly re-armed.

#include <cstdint>
#include <array>
#include <optional>
#include <set>
#include <string>

#include "edsp/actuator_bridge/bridge_state.h"
#include "edsp/actuator_bridge/ride_through.h"
#include "edsp/drive_io/drive_backend.h"
#include "edsp/node/fault.h"
#include "edsp/node/request_service.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/arm_t.hpp"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/timing_contract.h"

namespace edsp {

// Setpoints closer than this in planner time give no velocity of their own.
inline constexpr double kShortestFeedForwardBasisS = 2e-4;

struct BridgeOptions {
  std::string node_name = "actuator_bridge";
  std::int64_t session_id = 0;      // commands from any other session are refused
  std::int64_t stale_us = 50000;    // no valid command for this long: hold
  double max_leg_speed_m_s = -1.0;  // faster changes are jumps; < 0: the config's
                                    // [limits] leg_speed_max_m_s
  double rejoin_speed_m_s = 0.02;   // after a re-arm: how fast the held legs close on the stream
  double stop_decel_m_s2 = -1.0;    // late commands: the fastest leg's deceleration to rest;
                                    // < 0: the config's [motion] leg_accel_max_m_s2
};

class ActuatorBridge {
 public:
  // The backend must outlive the bridge. Starts holding the current position.
  ActuatorBridge(PlatformModel model, DriveBackend* backend, BridgeOptions options);

  // True: the command becomes the target, which the next cycle writes to
  // the drives (it touches no drive itself). False: *fault says why it was
  // refused.
  bool HandleCommand(const leg_command_t& command, std::int64_t now_utime, fault_t* fault);

  // One drive cycle: one Read, then hold if the target went stale or the
  // drives were lost, then one Write (drive_backend.h). Returns true and
  // fills *fault when a new fault arose this cycle.
  bool Cycle(std::int64_t now_utime, leg_state_t* state, fault_t* fault);
  // The setpoint instant of the last command written (0: a hold at rest);
  // while commands are late, the drives are told that command's motion
  // brought to rest (ride_through.h).
  std::int64_t written_setpoint_utime() const { return target_.utime; }

  // After a stale hold, or drives that stopped answering, the bridge refuses
  // every command until an operator re-arms it (the stream may come back
  // anywhere; resuming by itself when the trajectory happens to pass the
  // held pose would start the platform with a jerk). After Rearm() the
  // bridge rejoins the stream: the held legs go towards the latest command
  // along a straight line in leg space, far enough each cycle that the gap
  // shrinks at rejoin_speed_m_s however the stream moves (never beyond the
  // legs' speed limit), then follow it as before (caught up: within one
  // step). While rejoining, the stream itself must stay continuous (a jump
  // in it is refused, as ever). A bridge started (or restarted) into a
  // stream that is elsewhere refuses it as a jump until re-armed likewise.
  // Also resets drives that left operation (DriveBackend::Reset); false
  // with *error when that failed (still latched).
  bool Rearm(std::string* error = nullptr);
  // An operator's EDSP_ARM, answered as every request (request_service.h):
  // the reply to publish on EDSP_REPLY, done, or failed when the drives
  // could not be reset (still latched). A copy (edsp-ctl sends it again
  // until answered) gets the same reply and re-arms nothing again.
  RequestService<reply_t>::Answer HandleArm(const arm_t& arm, std::int64_t now_utime);
  BridgeState state() const { return state_; }
  bool rejoining() const { return IsRejoining(state_); }
  bool latched() const { return state_ == BridgeState::kLatched; }
  bool holding() const { return IsHolding(state_); }
  std::int64_t accepted() const { return accepted_; }
  std::int64_t rejected() const { return rejected_; }

 private:
  reply_t ActOnArm(const arm_t& arm);
  reply_t ArmReply(ReplyCode code, std::string reason) const;
  fault_t Fault(FaultCode code, std::string reason, std::int64_t now_utime) const;
  bool Reject(FaultCode code, std::string reason, std::int64_t now_utime, fault_t* fault);

  // HandleCommand's steps. A refusal: the fault's code and reason.
  struct Refusal {
    FaultCode code;
    std::string reason;
  };
  // How far a command may move a leg: at the legs' top speed, for the
  // planner time since the last accepted command (`basis`: its setpoint's
  // time) clamped to [one cycle, the stale limit]. `since_s` is that time
  // unclamped below: the velocity feed-forward is the step over it.
  struct StepLimit {
    std::int64_t basis_utime;
    double elapsed_s;
    double max_step_m;
    double since_s;
  };
  // Why the bridge takes no command now, whatever its lengths: latched,
  // starved past the stale limit (then it holds, as a cycle would have),
  // drives not read or not answering, another session, a stale or future
  // stamp. Nothing when it listens.
  std::optional<Refusal> WhyNotListening(const leg_command_t& c, std::int64_t now_utime);
  StepLimit StepLimitFor(const leg_command_t& c) const;
  // Why these lengths cannot be commanded: not finite, out of stroke, a
  // jump from the held target or the stream. Else the lengths in *command_m.
  std::optional<Refusal> WhyNotTheseLengths(const leg_command_t& c, const StepLimit& step, Vector6* command_m) const;
  // The command becomes the drives' target (while rejoining, a step towards it).
  void Accept(const leg_command_t& c, const Vector6& command_m, const StepLimit& step, std::int64_t now_utime);
  // A stream back after a silence, farther than a cycle's travel from
  // drives that stood on their watchdog meanwhile, is rejoined from where
  // they stand; the step limit the rejoin takes.
  StepLimit CatchAStreamThatWentOn(const Vector6& command_m, const StepLimit& step, std::int64_t now_utime);
  // The target this command allows: itself, or while rejoining a bounded
  // step towards it that closes the gap at the rejoin speed, a moving
  // stream's motion included (`stream_motion_m`: since its last command).
  // Ends the rejoin once the stream is within one step.
  // (Which may move the state: see Apply.)
  Vector6 NextTarget(const Vector6& command_m, const Vector6& stream_motion_m, double max_step_m, double elapsed_s,
                     bool* caught_up) const;
  // The state after `event` (bridge_state.h). An event the table does not
  // allow is a bug here: the bridge then latches, the safe side.
  void Apply(BridgeEvent event);
  bool Moving() const { return !IsHolding(state_); }
  // Since the last valid command arrived (0 before the first).
  std::int64_t SinceLastCommandUs(std::int64_t now_utime) const {
    return target_utime_ ? now_utime - *target_utime_ : 0;
  }
  // What this cycle writes: the target, or while commands are late its
  // motion ridden through (after a pause of this bridge's own since the
  // last command: what it last wrote, as it was).
  DriveSetpoint SetpointNow(std::int64_t now_utime) const;
  DriveSetpoint RiddenThrough(std::int64_t now_utime) const;  // the last command, continued or slowed
  // Where the drives come to rest on the motion under way: the ride-through's
  // end, or after a pause of this bridge, where they stopped by themselves.
  std::array<double, 6> RestAngles(std::int64_t now_utime) const;
  void KeepWithinStroke(DriveSetpoint* setpoint) const;
  void NoteOwnPause(std::int64_t now_utime);                // a cycle of this bridge too late
  void HoldAtRest(std::int64_t now_utime);                  // where the last valid command was brought to rest
  void HoldWhereTheDrivesAre();                             // after drives answer again
  bool LoseDrives(std::int64_t now_utime, fault_t* fault);  // hold at rest, latch; the fault
  // While the drives stay lost, each new reason from the backend (refused →
  // timed out → drive 3 in fault 8130h) is reported once per outage, the
  // latest one, at most every 100 ms (FaultThrottle would swallow one sooner).
  bool ReportNewReason(std::int64_t now_utime, fault_t* fault);

  PlatformModel model_;
  DriveBackend* backend_;
  BridgeOptions options_;
  RequestService<reply_t> arm_requests_{RequestPolicy{options_.session_id, 5.0, true}};  // a late re-arm never acts
  DriveSetpoint target_;                                                                 // what the drives are told
  Vector6 target_length_m_;
  BridgeState state_ = BridgeState::kStartupHold;
  const char* latch_cause_ = "";              // why it is latched, for the refusals that follow
  std::optional<std::int64_t> target_utime_;  // receipt time of the last valid command
  std::int64_t last_cycle_utime_ = -1;
  bool paused_since_command_ = false;  // this bridge itself, since the last valid command
  // What the drives were last told since the last valid command (its own
  // setpoint, or the motion ridden through): a pause of this bridge repeats it.
  std::optional<DriveSetpoint> written_since_command_;
  RideThrough ride_;                   // how the last valid command is brought to rest
  std::int64_t last_basis_utime_ = 0;  // its planner time (setpoint_utime)
  std::int64_t last_command_seq_ = 0;
  bool backend_ok_ = true;                  // drive health, an input: faults are raised on its changes
  std::set<std::string> reported_reasons_;  // the backend's reasons reported in this outage
  std::int64_t backend_report_utime_ = 0;   // when the last of them was
  // Where a hold holds, not whether (data, not state: the table says
  // whether): set when a command found this bridge starved past the stale
  // limit (it was frozen), the next cycle holding the drives where its read
  // finds them rather than at the last command.
  bool hold_where_the_drives_are_ = false;
  Vector6 stream_length_m_;  // the last valid command (= target unless rejoining)
  std::int64_t state_seq_ = 0;
  std::int64_t accepted_ = 0;
  std::int64_t rejected_ = 0;
  DriveFeedback feedback_;
};

}  // namespace edsp
