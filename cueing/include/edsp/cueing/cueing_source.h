#pragma once
// What edsp-cueing does each cycle, free of any bus or socket: the
// vehicle's packets in (through VehicleInput's guard), whether the
// planner's setpoints follow this source, and out the cue setpoint to
// publish (EDSP_CUE_SETPOINT) and the motion request to send. The host's
// command word, sent in every packet, drives it:
//   engage     from disengaged: ask the planner to engage (its checked move
//              to the neutral pose; the cue waits there), then wash out the
//              input, faded in from a rider at rest over [input] fade_s;
//   disengage  fade the input out to rest, let the washout bring the head
//              home, then ask the planner to disengage at the neutral pose;
//   freeze     brake the cue to rest and hold it there; left by disengage,
//              or by engage once at rest: the washout starts again from
//              rest, its input faded in as at engage, and the cue returns
//              from where the freeze held it along a raised cosine no
//              harder than the freeze's brake;
//   e-stop     ask the planner to stop at once: its setpoints hold where
//              they are (left by disengage, then engage).
// A request refused, or the planner ending the cueing by itself (a cue it
// could not follow, an operator's halt), stops it the same way, with the
// reason. An input that is lost fades to rest (VehicleInput): the washout
// brings the platform home, still engaged.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "edsp/cueing/classical_washout.h"
#include "edsp/cueing/cueing_algorithm.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/vehicle_input.h"
#include "edsp/kinematics/pose.h"

namespace edsp {

enum class CueingPhase { kDisengaged, kEngaging, kEngaged, kFrozen, kWashingOut, kDisengaging, kStopped };
const char* CueingPhaseName(CueingPhase phase);

enum class CueRequest { kEngage, kDisengage, kStop };

struct CueSetpoint {
  Vector6 pose = Vector6::Zero();  // {M} in {B}: x y z (m), roll pitch yaw (rad)
  Vector6 velocity = Vector6::Zero();
  Vector6 acceleration = Vector6::Zero();
};

struct CueingStep {
  std::optional<CueSetpoint> cue;     // to publish now (engaging, engaged, washing out, frozen, disengaging)
  std::optional<CueRequest> request;  // to send now (at most one in flight)
  double time_s = 0.0;                // the time the cue is of: its stamp (the source's clock)
  std::uint32_t input_sequence = 0;   // the newest vehicle packet's when the cue was made (0: none yet)
};

// How hard a frozen cue brakes to rest: well inside any leg's acceleration
// limit, and a cue's speeds (centimetres, degrees per second) stop in
// tenths of a second.
inline constexpr double kFreezeBrake_m_s2 = 1.0;
inline constexpr double kFreezeBrake_rad_s2 = 1.0;
// Washed out: the head this near its neutral pose, and still.
inline constexpr double kHomeTolerance_m = 1e-4;
inline constexpr double kHomeTolerance_rad = 1e-4;
inline constexpr double kHomeSpeed = 1e-3;  // m/s and rad/s
// At most this many washout steps to catch up on cycles the host delayed
// (20 periods: at the stack's 1 kHz, the planner's default stale limit).
inline constexpr long kMaxCatchUpSteps = 20;
// The washout given this long to bring the head home before disengaging anyway.
inline constexpr double kWashoutTimeout_s = 30.0;

class CueingSource {
 public:
  // `filter`: the cueing algorithm (MakeCueingFilter, about the model's
  // home pose: `neutral_pose` should be it); none: classical washout with
  // the config's parameters. Throws std::invalid_argument naming a parameter that is absurd.
  CueingSource(const CueingConfig& config, const Vector6& neutral_pose, std::unique_ptr<CueingFilter> filter = nullptr);

  // A packet that arrived at `now_s` (monotonic): nothing if accepted, else why not.
  std::optional<std::string> OnPacket(const VehiclePacket& packet, double now_s);
  // The planner's answer to the request last sent.
  void OnReply(CueRequest request, bool accepted, const std::string& reason);
  // From the planner's motion status: whether its setpoints follow this source now.
  void OnPlannerFollows(bool follows, const std::string& reason);
  // One cycle at `now_s`. The source's clock advances in whole periods, so
  // that a cue is of the time it is stamped with: a cycle woken late runs
  // the periods it missed (at most kMaxCatchUpSteps), one woken early after
  // it runs none and gives nothing but an e-stop's request; a wall clock
  // stepped back takes the source's clock with it.
  CueingStep Step(double now_s);

  CueingPhase phase() const { return phase_; }
  const std::string& why_stopped() const { return why_; }
  const VehicleInput& input() const { return input_; }
  const Vector6& neutral_pose() const { return neutral_; }

 private:
  int DueSteps(double now_s);
  std::optional<CueingStep> EStop(double now_s);
  CueSetpoint Wash(const VehicleSample& input, double gain, double now_s);
  void Resume(double now_s);
  Vector6 ReturnOffset(double now_s) const;
  CueSetpoint Brake();
  CueSetpoint Held() const;
  void Stop(std::string why);
  bool HeadHome(const HeadCue& head, const CueSetpoint& cue) const;

  CueingConfig config_;
  double period_s_;
  Vector6 neutral_;
  VehicleInput input_;
  std::unique_ptr<CueingFilter> filter_;  // reset at each engage
  CueingPhase phase_ = CueingPhase::kDisengaged;
  bool awaiting_reply_ = false;
  bool planner_follows_ = false;
  double engaged_s_ = 0.0;   // when the planner began following
  double fade_out_s_ = 0.0;  // when the washing out began
  double gain_at_fade_out_ = 0.0;
  // Leaving a freeze: the cue's offset from where the restarted washout
  // puts it, brought to nothing over return_s_ from return_start_s_.
  Vector6 return_from_ = Vector6::Zero();
  double return_start_s_ = 0.0;
  double return_s_ = 1.0;
  HeadCue head_;      // the washout's last output
  CueSetpoint last_;  // the cue published last
  std::string why_;
  bool clock_started_ = false;  // the source's clock: origin_s_ + periods_ * period_s_, from the first cycle
  double origin_s_ = 0.0;
  std::int64_t periods_ = 0;
  int steps_ = 1;  // washout (or brake) steps this cycle: the periods its clock advanced
};

}  // namespace edsp
