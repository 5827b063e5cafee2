#pragma once
// The kinematics node's logic, free of any bus (the edsp-kinematics process
// wires it to edsp::Bus): setpoint → leg command with PR compensation in the
// configured (live-switchable) mode; encoder feedback → platform state by
// forward kinematics with PR; the platform config message; with a
// calibration, the identified effects compensated in both. A setpoint it
// cannot validate is never forwarded: it yields a fault instead.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "edsp/node/fault.h"
#include "edsp/node/request_service.h"
#include "edsp/calibration_t.hpp"
#include "edsp/pr_mode_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/calibration_blend.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/platform_config_t.hpp"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

struct KinematicsNodeOptions {
  std::string node_name = "kinematics";
  PrMode pr_mode = PrMode::kSigned;
  std::int64_t session_id = 0;        // setpoints from any other session are refused
  std::int64_t stale_us = 50000;      // setpoints older than this are refused
  std::int64_t pr_blend_us = 500000;  // a live mode switch blends over this much setpoint time
  // Applied to every command and to forward kinematics (calibration.h);
  // none: the nominal model alone.
  std::optional<calibration::CalibrationModel> calibration;
  // A calibration switched live blends over this much setpoint time (not a
  // setting: a test's).
  std::int64_t calibration_blend_us = 1000000;
  // A calibration in force at start blends in, its fastest leg at 5% of the
  // legs' speed limit, from where the drives hold (their first reading, NoteDrives) rather than
  // stepping the first command by its correction at home, which the bridge
  // refuses as a jump once it is more than a cycle's travel. A setpoint
  // before any reading is then refused. Off for a replay (no drives).
  bool calibration_starts_from_drives = true;
};

class KinematicsNode {
 public:
  KinematicsNode(PlatformModel model, KinematicsNodeOptions options);

  // True: *command is the leg command for the setpoint. False: *fault says why.
  bool HandleSetpoint(const pose_setpoint_t& setpoint, std::int64_t now_utime, leg_command_t* command, fault_t* fault);

  // Where the drives hold (their encoders' lengths), from every reading:
  // where a calibration in force at start blends in from.
  void NoteDrives(const leg_state_t& legs);

  // True: *state is the pose the encoders imply. False: *fault says why.
  bool HandleLegState(const leg_state_t& legs, std::int64_t now_utime, platform_state_t* state, fault_t* fault);

  // The config latched on EDSP_CONFIG; `config_toml` is the file's text.
  platform_config_t ConfigMessage(std::int64_t now_utime, const std::string& config_toml);

  // Switches the PR mode live. The correction moves from the old mode's to
  // the new one's linearly over pr_blend_us of setpoint time, starting at the
  // next setpoint: switching none → signed at Rz 30° is a 1.4 mm change,
  // which in one step the bridge would (rightly) refuse as a jump.
  void SwitchPrMode(PrMode mode);
  // An operator's EDSP_PR_MODE, answered as every request (request_service.h):
  // switches (blended) and returns the reply to publish on EDSP_REPLY, done
  // or why not. A copy gets the same reply and switches nothing.
  RequestService<reply_t>::Answer HandlePrModeRequest(const pr_mode_t& request, std::int64_t now_utime);
  // Switches the calibration live (null: the nominal model alone), blended
  // over calibration_blend_us of setpoint time from the next setpoint on.
  // False, *why_not saying so, while the last switch still blends.
  bool SwitchCalibration(std::optional<calibration::CalibrationModel> next, std::string* why_not);
  // An operator's EDSP_CALIBRATION, answered likewise: the model in the
  // request is checked against this platform as at start-up (calibration.h)
  // and switched to, blended. The reply names file, hash and effects, or
  // why it was refused (the calibration in force stays).
  RequestService<reply_t>::Answer HandleCalibrationRequest(const calibration_t& request, std::int64_t now_utime);
  PrMode pr_mode() const { return options_.pr_mode; }
  bool blending() const { return blending_; }
  const PlatformModel& model() const { return model_; }
  // The calibration switched to last, or null: the one in force once no
  // blend runs (calibration_blending()).
  const calibration::CalibrationModel* calibration() const { return calibration_.target(); }
  bool calibration_blending() const { return calibration_.blending(); }
  // "none", the model in force (file, hash, effects), or "blending from A
  // to B (40% of 1000 ms)".
  std::string DescribeCalibration() const;

 private:
  fault_t Fault(FaultCode code, std::string reason, std::int64_t now_utime, const char* channel) const;
  Vector6 BlendedPrError(const LegSolution& legs, std::int64_t setpoint_utime);
  reply_t ActOnPrModeRequest(const pr_mode_t& request);
  reply_t ActOnCalibrationRequest(const calibration_t& request);
  reply_t Reply(const char* channel, ReplyCode code, std::string reason) const;
  // The calibration's correction of the nominal command for `sp`; false
  // (*fault) when it is not finite: never forwarded.
  bool ApplyCalibration(const pose_setpoint_t& sp, const Pose& target, const Vector6& nominal, std::int64_t now_utime,
                        Vector6* calibrated, fault_t* fault);
  // At the first command of a calibration in force at start: how much of
  // its correction the drives already carry (0..1), and the blend from it.
  void StartCalibrationFromTheDrives(const Vector6& nominal, calibration::LegCompensator::Correction* c);

  PlatformModel model_;
  KinematicsNodeOptions options_;
  // Switches: a late request never undoes a later one.
  RequestService<reply_t> pr_mode_requests_{RequestPolicy{options_.session_id, 5.0, true}};
  RequestService<reply_t> calibration_requests_{RequestPolicy{options_.session_id, 5.0, true}};
  std::int64_t command_seq_ = 0;
  std::int64_t state_seq_ = 0;
  std::int64_t config_seq_ = 0;
  // The correction is a mix of the modes' corrections: one-hot at rest, and
  // during a blend (1−a)·from + a·one-hot(pr_mode). A switch mid-blend starts
  // from the mix in force, so the correction never steps.
  using ModeWeights = std::array<double, 4>;
  ModeWeights Weights(std::int64_t setpoint_utime) const;
  ModeWeights blend_from_{};
  ModeWeights last_weights_{};
  bool blending_ = false;
  std::optional<std::int64_t> blend_start_utime_;  // setpoint time the blend began; none: next setpoint
  Pose last_target_;
  Pose last_estimate_;
  calibration::CalibrationBlend calibration_;
  Vector6 encoder_correction_ = Vector6::Zero();  // the calibration's, at the last command
  bool calibration_start_pending_ = false;        // a calibration in force at start, no command yet
  std::optional<Vector6> drives_m_;               // the drives' last reading (encoder lengths)
};

}  // namespace edsp
