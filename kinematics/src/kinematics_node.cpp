#include "edsp/kinematics/kinematics_node.h"

#include <algorithm>

#include <cmath>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/workspace.h"
#include "edsp/node/fault.h"
#include "edsp/node/stamp_check.h"

namespace edsp {

namespace {

// A calibration in force at start blends in with its fastest leg at this
// share of the legs' speed limit.
constexpr double kStartPace = 0.05;

template <std::size_t N>
bool AllFinite(const double (&values)[N]) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

std::unique_ptr<calibration::LegCompensator> Compensator(const PlatformModel& model,
                                                         std::optional<calibration::CalibrationModel> calibration) {
  if (!calibration) return nullptr;
  return std::make_unique<calibration::LegCompensator>(model, std::move(*calibration));
}

}  // namespace

KinematicsNode::KinematicsNode(PlatformModel model, KinematicsNodeOptions options)
    : model_(std::move(model)),
      options_(std::move(options)),
      last_target_(model_.home_pose()),
      last_estimate_(model_.home_pose()),
      calibration_(Compensator(model_, options_.calibration), options_.calibration_blend_us),
      calibration_start_pending_(options_.calibration.has_value() && options_.calibration_starts_from_drives) {
  last_weights_[static_cast<std::size_t>(options_.pr_mode)] = 1.0;
}

fault_t KinematicsNode::Fault(FaultCode code, std::string reason, std::int64_t now_utime, const char* channel) const {
  return MakeFault(options_.node_name, channel, code, fault_t::SEVERITY_ERROR, std::move(reason), now_utime);
}

reply_t KinematicsNode::Reply(const char* channel, ReplyCode code, std::string reason) const {
  reply_t reply{};
  reply.node = options_.node_name;
  reply.request_channel = channel;
  reply.code = static_cast<std::int8_t>(code);
  reply.reason = std::move(reason);
  return reply;
}

RequestService<reply_t>::Answer KinematicsNode::HandlePrModeRequest(const pr_mode_t& request, std::int64_t now_utime) {
  return pr_mode_requests_.Handle(
      request, now_utime,
      [&](ReplyCode code, const std::string& reason) {
        return Reply(channel::kPrMode, code,
                     fmt::format("PR mode {}; mode stays {}", reason, PrModeName(options_.pr_mode)));
      },
      [&] { return ActOnPrModeRequest(request); });
}

reply_t KinematicsNode::ActOnPrModeRequest(const pr_mode_t& request) {
  PrMode mode;
  const std::string text = std::to_string(request.pr_mode);
  if (!ParsePrMode(text.c_str(), &mode)) {
    return Reply(channel::kPrMode, ReplyCode::kInvalid,
                 fmt::format("PR mode {} from {} is not 0..3; mode stays {}", text, request.operator_name,
                             PrModeName(options_.pr_mode)));
  }
  const PrMode before = options_.pr_mode;
  SwitchPrMode(mode);
  return Reply(channel::kPrMode, ReplyCode::kDone,
               fmt::format("PR mode {} → {} (requested by {}), blended over {} ms", PrModeName(before),
                           PrModeName(mode), request.operator_name, options_.pr_blend_us / 1000));
}

RequestService<reply_t>::Answer KinematicsNode::HandleCalibrationRequest(const calibration_t& request,
                                                                         std::int64_t now_utime) {
  return calibration_requests_.Handle(
      request, now_utime,
      [&](ReplyCode code, const std::string& reason) {
        return Reply(channel::kCalibration, code,
                     fmt::format("calibration {}; in force stays {}", reason, DescribeCalibration()));
      },
      [&] { return ActOnCalibrationRequest(request); });
}

reply_t KinematicsNode::ActOnCalibrationRequest(const calibration_t& request) {
  auto refuse = [&](ReplyCode code, const std::string& why) {
    return Reply(channel::kCalibration, code,
                 fmt::format("calibration {} from {} refused: {}; in force stays {}", request.origin,
                             request.operator_name, why, DescribeCalibration()));
  };
  std::optional<calibration::CalibrationModel> next;
  if (!request.model_json.empty()) {
    try {
      next = calibration::ParseCalibration(request.model_json, request.origin, model_, request.apply_ambiguous != 0);
    } catch (const calibration::CalibrationError& e) {
      return refuse(ReplyCode::kInvalid, e.what());
    }
  }
  const std::string before = DescribeCalibration();
  const std::string after = next ? next->Describe() : "none";
  std::string why_not;
  if (!SwitchCalibration(std::move(next), &why_not)) return refuse(ReplyCode::kNotNow, why_not);
  return Reply(channel::kCalibration, ReplyCode::kDone,
               fmt::format("calibration {} → {} (requested by {}), blended over {} ms", before, after,
                           request.operator_name, calibration_.blend_us() / 1000));
}

std::string KinematicsNode::DescribeCalibration() const {
  auto name = [](const calibration::CalibrationModel* c) { return c ? c->Describe() : std::string("none"); };
  if (!calibration_.blending()) return name(calibration_.target());
  return fmt::format("blending from {} to {} ({:.0f}% of {} ms)", name(calibration_.source()),
                     name(calibration_.target()), 100.0 * calibration_.weight(),
                     calibration_.running_blend_us() / 1000);
}

bool KinematicsNode::SwitchCalibration(std::optional<calibration::CalibrationModel> next, std::string* why_not) {
  if (calibration_start_pending_) {
    // Nothing commanded yet: the new model is the one in force at start,
    // and it starts from the drives in its turn (none: nothing to start).
    calibration_start_pending_ = next.has_value();
    calibration_ = calibration::CalibrationBlend(Compensator(model_, std::move(next)), options_.calibration_blend_us);
    return true;
  }
  return calibration_.SwitchTo(Compensator(model_, std::move(next)), why_not);
}

void KinematicsNode::SwitchPrMode(PrMode mode) {
  if (mode == options_.pr_mode) return;  // already there, or on the way: carry on
  blend_from_ = last_weights_;
  options_.pr_mode = mode;
  blending_ = true;
  blend_start_utime_.reset();
}

KinematicsNode::ModeWeights KinematicsNode::Weights(std::int64_t setpoint_utime) const {
  ModeWeights target{};
  target[static_cast<std::size_t>(options_.pr_mode)] = 1.0;
  if (!blending_) return target;
  const std::int64_t start = blend_start_utime_.value_or(setpoint_utime);
  // In double: setpoint stamps are the sender's word, any int64.
  const double a = std::clamp((static_cast<double>(setpoint_utime) - static_cast<double>(start)) /
                                  static_cast<double>(std::max<std::int64_t>(options_.pr_blend_us, 1)),
                              0.0, 1.0);
  ModeWeights w{};
  for (std::size_t m = 0; m < w.size(); ++m) w[m] = (1.0 - a) * blend_from_[m] + a * target[m];
  return w;
}

Vector6 KinematicsNode::BlendedPrError(const LegSolution& legs, std::int64_t setpoint_utime) {
  if (blending_ && !blend_start_utime_) blend_start_utime_ = setpoint_utime;
  last_weights_ = Weights(setpoint_utime);
  if (blending_ && last_weights_[static_cast<std::size_t>(options_.pr_mode)] >= 1.0) blending_ = false;
  Vector6 pr = Vector6::Zero();
  for (std::size_t m = 0; m < last_weights_.size(); ++m) {
    if (last_weights_[m] != 0.0) pr += last_weights_[m] * model_.PrLengthError(legs, static_cast<PrMode>(m));
  }
  return pr;
}

bool KinematicsNode::HandleSetpoint(const pose_setpoint_t& sp, std::int64_t now_utime, leg_command_t* command,
                                    fault_t* fault) {
  constexpr const char* kChannel = channel::kSetpoint;
  if (sp.session_id != options_.session_id) {
    *fault = Fault(FaultCode::kForeignSession,
                   fmt::format("setpoint seq {} from session {}, this group is session {}", sp.seq, sp.session_id,
                               options_.session_id),
                   now_utime, kChannel);
    return false;
  }
  if (!AllFinite(sp.pose) || !AllFinite(sp.velocity) || !AllFinite(sp.acceleration)) {
    *fault = Fault(FaultCode::kNonFinite,
                   fmt::format("setpoint seq {} has a non-finite pose, velocity or acceleration", sp.seq), now_utime,
                   kChannel);
    return false;
  }
  const std::string what = fmt::format("setpoint seq {}", sp.seq);
  if (std::optional<std::string> stamp = StampProblem(what, sp.utime, now_utime, options_.stale_us)) {
    *fault = Fault(FaultCode::kStale, std::move(*stamp), now_utime, kChannel);
    return false;
  }
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = sp.pose[k];
  const Pose target = Pose::FromVector(q);
  const WorkspaceCheck check = CheckWorkspace(model_, target);
  if (!check.ok()) {
    *fault = Fault(FaultCode::kOutsideWorkspace,
                   fmt::format("setpoint seq {} ({}): {}", sp.seq, DescribePose(target), check.Describe()), now_utime,
                   kChannel);
    return false;
  }
  const LegSolution legs = model_.Solve(target);
  const Vector6 pr = BlendedPrError(legs, sp.utime);
  const Vector6 nominal = legs.length_m - pr;
  Vector6 calibrated;
  if (!ApplyCalibration(sp, target, nominal, now_utime, &calibrated, fault)) return false;
  *command = leg_command_t{};
  command->utime = now_utime;
  command->seq = ++command_seq_;
  command->session_id = options_.session_id;
  command->setpoint_utime = sp.utime;
  command->setpoint_seq = sp.seq;
  command->pr_mode = static_cast<std::int8_t>(options_.pr_mode);
  for (int i = 0; i < kNumLegs; ++i) {
    command->ik_length_m[i] = legs.length_m(i);
    command->pr_correction_m[i] = pr(i);
    command->command_length_m[i] = calibrated(i);
    command->motor_angle_rad[i] = model_.MotorAngleFromLength(i, command->command_length_m[i]);
  }
  last_target_ = target;
  return true;
}

bool KinematicsNode::ApplyCalibration(const pose_setpoint_t& sp, const Pose& target, const Vector6& nominal,
                                      std::int64_t now_utime, Vector6* calibrated, fault_t* fault) {
  Vector6 velocity, acceleration;
  for (int k = 0; k < 6; ++k) velocity(k) = sp.velocity[k], acceleration(k) = sp.acceleration[k];
  if (calibration_start_pending_ && !drives_m_) {
    *fault = Fault(FaultCode::kStale,
                   fmt::format("setpoint seq {}: no reading of the drives yet; the calibration in force at start "
                               "blends in from where they hold; not forwarded",
                               sp.seq),
                   now_utime, channel::kSetpoint);
    return false;
  }
  calibration::LegCompensator::Correction c = calibration_.Step(sp.utime, target, velocity, acceleration, nominal);
  if (calibration_start_pending_) StartCalibrationFromTheDrives(nominal, &c);
  if (!c.command_m.allFinite() || !c.encoder_m.allFinite()) {
    *fault = Fault(FaultCode::kNonFinite,
                   fmt::format("setpoint seq {} ({}): the calibration's correction is not finite; not forwarded",
                               sp.seq, DescribePose(target)),
                   now_utime, channel::kSetpoint);
    return false;
  }
  *calibrated = nominal - c.command_m;
  encoder_correction_ = c.encoder_m;
  return true;
}

void KinematicsNode::StartCalibrationFromTheDrives(const Vector6& nominal, calibration::LegCompensator::Correction* c) {
  calibration_start_pending_ = false;
  // The share of the correction that puts the command nearest the drives:
  // 0 where they hold at the nominal command, 1 where they already carry
  // the calibration (a restarted kinematics node). Anything else the bridge
  // judges as it would without a calibration.
  const double squared = c->command_m.squaredNorm();
  if (!(squared > 0.0)) return;
  const double weight = std::clamp((nominal - *drives_m_).dot(c->command_m) / squared, 0.0, 1.0);
  if (!(weight < 1.0 - 1e-6)) return;  // a millionth of it short: the rounding of the drives' reading
  // Its fastest leg at kStartPace of the legs' speed limit: a correction of
  // millimetres in tenths of a second, one of tenths of a millimetre in a
  // few cycles (few tracker samples see it while the platform moves).
  const double pace_m_s = kStartPace * model_.config().limits.leg_speed_max_m_s;
  const double blend_s = c->command_m.cwiseAbs().maxCoeff() / pace_m_s;
  calibration_.BlendInFrom(weight, std::max<std::int64_t>(std::llround(std::ceil(blend_s * 1e3)) * 1000, 1000));
  c->command_m *= weight;
  c->encoder_m *= weight;
}

void KinematicsNode::NoteDrives(const leg_state_t& legs) {
  if (!AllFinite(legs.encoder_length_m)) return;
  Vector6 lengths;
  for (int i = 0; i < kNumLegs; ++i) lengths(i) = legs.encoder_length_m[i];
  drives_m_ = lengths;
}

bool KinematicsNode::HandleLegState(const leg_state_t& legs, std::int64_t now_utime, platform_state_t* state,
                                    fault_t* fault) {
  constexpr const char* kChannel = channel::kLegState;
  if (!AllFinite(legs.encoder_length_m)) {
    *fault = Fault(FaultCode::kNonFinite, fmt::format("leg state seq {} has a non-finite encoder length", legs.seq),
                   now_utime, kChannel);
    return false;
  }
  NoteDrives(legs);
  Vector6 lengths;
  for (int i = 0; i < kNumLegs; ++i) lengths(i) = legs.encoder_length_m[i] + encoder_correction_(i);
  const FkResult fk = SolveForward(model_, lengths, last_estimate_);
  if (!fk.ok()) {
    *fault = Fault(FaultCode::kForwardKinematics,
                   fmt::format("leg state seq {}: forward kinematics {} (residual {:.3g} m)", legs.seq,
                               FkStatusName(fk.status), fk.residual_m),
                   now_utime, kChannel);
    return false;
  }
  last_estimate_ = fk.pose;
  *state = platform_state_t{};
  state->utime = now_utime;
  state->seq = ++state_seq_;
  const Vector6 pose = fk.pose.ToVector(), target = last_target_.ToVector();
  const Vector3 a = model_.ObservationPoint(fk.pose);
  for (int k = 0; k < 6; ++k) {
    state->pose[k] = pose(k);
    state->target_pose[k] = target(k);
  }
  for (int k = 0; k < 3; ++k) state->observation_point_m[k] = a(k);
  state->fk_status = static_cast<std::int8_t>(fk.status);
  state->fk_residual_m = fk.residual_m;
  return true;
}

platform_config_t KinematicsNode::ConfigMessage(std::int64_t now_utime, const std::string& config_toml) {
  const PlatformConfig& c = model_.config();
  platform_config_t msg{};
  msg.utime = now_utime;
  msg.seq = ++config_seq_;
  msg.preset = c.preset;
  for (int i = 0; i < kNumLegs; ++i) {
    for (int k = 0; k < 3; ++k) {
      msg.base_joints_m[i][k] = c.geometry.p_BoBi_B(k, i);
      msg.platform_joints_m[i][k] = c.geometry.p_MoPi_M(k, i);
      msg.base_axes[i][k] = c.geometry.ja_B(k, i);
      msg.platform_axes[i][k] = c.geometry.jd_M(k, i);
    }
  }
  msg.home_height_m = c.geometry.home_height_m;
  msg.lead_m = c.drive.lead_m;
  msg.pr_sign = static_cast<std::int8_t>(c.drive.pr_sign);
  msg.gear_ratio = c.drive.gear_ratio;
  msg.leg_min_m = c.limits.leg_min_m;
  msg.leg_max_m = c.limits.leg_max_m;
  msg.joint_angle_max_rad = c.limits.joint_angle_max_rad;
  for (int k = 0; k < 3; ++k) msg.observation_point_m[k] = c.p_MoA_M(k);
  msg.config_toml = config_toml;
  // The calibration in force travels with the latched config, so a log (and
  // a late listener) says which model shaped its commands.
  if (calibration_.blending()) {
    msg.config_toml += "\n# edsp-kinematics switches the calibration: " + DescribeCalibration() + "\n";
  } else if (const calibration::CalibrationModel* in_force = calibration()) {
    msg.config_toml += "\n# edsp-kinematics applies the calibration " + in_force->Describe() + "\n";
  }
  return msg;
}

}  // namespace edsp
