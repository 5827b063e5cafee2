#include "edsp/cueing/cueing_source.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "edsp/cueing/raised_cosine.h"

namespace edsp {

namespace {

// `sample` moved towards a rider at rest (gravity, no rotation): all of it at
// gain 1, none at 0.
VehicleSample TowardsRest(const VehicleSample& sample, double gain) {
  const VehicleSample rest;
  VehicleSample out = sample;
  out.specific_force_m_s2 = rest.specific_force_m_s2 + gain * (sample.specific_force_m_s2 - rest.specific_force_m_s2);
  out.angular_velocity_rad_s = gain * sample.angular_velocity_rad_s;
  return out;
}

// `v` slowed by at most `brake` (a speed), its direction kept.
Vector3 Slowed(const Vector3& v, double brake) {
  const double speed = v.norm();
  return speed <= brake ? Vector3::Zero() : Vector3(v * ((speed - brake) / speed));
}

}  // namespace

const char* CueingPhaseName(CueingPhase phase) {
  switch (phase) {
    case CueingPhase::kDisengaged: return "disengaged";
    case CueingPhase::kEngaging: return "engaging";
    case CueingPhase::kEngaged: return "engaged";
    case CueingPhase::kFrozen: return "frozen";
    case CueingPhase::kWashingOut: return "washing out";
    case CueingPhase::kDisengaging: return "disengaging";
    case CueingPhase::kStopped: return "stopped";
  }
  return "?";
}

CueingSource::CueingSource(const CueingConfig& config, const Vector6& neutral_pose,
                           std::unique_ptr<CueingFilter> filter)
    : config_(config),
      period_s_(1.0 / config.rate_hz),
      neutral_(neutral_pose),
      input_(config.input),
      filter_(std::move(filter)) {
  if (!neutral_pose.allFinite()) throw std::invalid_argument("cueing: the neutral pose is not finite");
  if (!(config.rate_hz > 0.0) || !std::isfinite(config.rate_hz)) {
    throw std::invalid_argument(fmt::format("cueing: rate_hz = {}: must be finite and > 0", config.rate_hz));
  }
  ValidateWashout(config.washout);
  if (filter_ == nullptr) filter_ = MakeClassicalWashout(config.washout, period_s_);
  last_.pose = neutral_;
}

std::optional<std::string> CueingSource::OnPacket(const VehiclePacket& packet, double now_s) {
  return input_.Accept(packet, now_s);
}

void CueingSource::OnReply(CueRequest request, bool accepted, const std::string& reason) {
  awaiting_reply_ = false;
  if (request == CueRequest::kDisengage && accepted) {
    phase_ = CueingPhase::kDisengaged;
    return;
  }
  if (!accepted && request != CueRequest::kStop) {
    Stop(fmt::format("{} refused by the planner: {}", request == CueRequest::kEngage ? "engage" : "disengage", reason));
  }
}

void CueingSource::OnPlannerFollows(bool follows, const std::string& reason) {
  const bool was = planner_follows_;
  planner_follows_ = follows;
  if (was && !follows &&
      (phase_ == CueingPhase::kEngaged || phase_ == CueingPhase::kFrozen || phase_ == CueingPhase::kWashingOut)) {
    Stop("the planner ended the cueing: " + (reason.empty() ? std::string("no reason given") : reason));
  }
}

void CueingSource::Stop(std::string why) {
  phase_ = CueingPhase::kStopped;
  why_ = std::move(why);
}

CueSetpoint CueingSource::Held() const {
  CueSetpoint held;
  held.pose = last_.pose;
  return held;
}

Vector6 CueingSource::ReturnOffset(double now_s) const {
  if (return_from_.isZero(0.0)) return Vector6::Zero();
  return return_from_ * (1.0 - RaisedCosine((now_s - return_start_s_) / return_s_));
}

void CueingSource::Resume(double now_s) {
  filter_->Reset();
  head_ = HeadCue{};  // the restarted washout's cue: neutral, at rest
  engaged_s_ = now_s;
  return_from_ = last_.pose - neutral_;
  return_start_s_ = now_s;
  // A raised cosine of amplitude A over T peaks at π²A/(2T²): no harder than the brake.
  const auto no_harder = [](double amplitude, double limit) { return kPi * std::sqrt(amplitude / (2.0 * limit)); };
  return_s_ = std::max({config_.input.fade_s, no_harder(return_from_.head<3>().norm(), kFreezeBrake_m_s2),
                        no_harder(return_from_.tail<3>().norm(), kFreezeBrake_rad_s2)});
  phase_ = CueingPhase::kEngaged;
}

CueSetpoint CueingSource::Wash(const VehicleSample& input, double gain, double now_s) {
  // One washout step per period the source's clock advanced: a cycle the
  // host's scheduler delayed must not leave the cue behind its stamp.
  const VehicleSample sample = TowardsRest(input, gain);
  for (int k = 0; k < steps_; ++k) head_ = filter_->Step(sample);
  const double dt = period_s_ * steps_;
  CueSetpoint cue;
  cue.pose =
      CueToPlatformPose(Pose::FromVector(neutral_), config_.head_in_platform_m, head_).ToVector() + ReturnOffset(now_s);
  cue.velocity = (cue.pose - last_.pose) / dt;
  cue.acceleration = (cue.velocity - last_.velocity) / dt;
  return cue;
}

CueSetpoint CueingSource::Brake() {
  CueSetpoint cue = last_;
  for (int k = 0; k < steps_; ++k) {
    cue.velocity.head<3>() = Slowed(cue.velocity.head<3>(), kFreezeBrake_m_s2 * period_s_);
    cue.velocity.tail<3>() = Slowed(cue.velocity.tail<3>(), kFreezeBrake_rad_s2 * period_s_);
    cue.pose += cue.velocity * period_s_;
  }
  cue.acceleration = (cue.velocity - last_.velocity) / (period_s_ * steps_);
  return cue;
}

bool CueingSource::HeadHome(const HeadCue& head, const CueSetpoint& cue) const {
  return head.position_m.norm() <= kHomeTolerance_m && head.rpy_rad.norm() <= kHomeTolerance_rad &&
         cue.velocity.head<3>().norm() <= kHomeSpeed && cue.velocity.tail<3>().norm() <= kHomeSpeed;
}

int CueingSource::DueSteps(double now_s) {
  if (!clock_started_) {
    clock_started_ = true;
    origin_s_ = now_s;
    return 1;
  }
  long due = std::lround((now_s - origin_s_) / period_s_) - periods_;
  if (due < -1) {  // the wall clock was stepped back: the source's follows it, one period on
    origin_s_ = now_s - static_cast<double>(periods_ + 1) * period_s_;
    due = 1;
  }
  if (due > kMaxCatchUpSteps) {  // a stall longer than the catch-up: the washout skips the rest
    periods_ += due - kMaxCatchUpSteps;
    due = kMaxCatchUpSteps;
  }
  due = std::max(due, 0L);
  periods_ += due;
  return static_cast<int>(due);
}

std::optional<CueingStep> CueingSource::EStop(double now_s) {
  // An e-stop wins over everything but a cueing that never started.
  if (input_.command() != CueCommand::kEStop || phase_ == CueingPhase::kDisengaged || phase_ == CueingPhase::kStopped) {
    return std::nullopt;
  }
  CueingStep out;
  out.time_s = now_s;
  out.request = CueRequest::kStop;
  awaiting_reply_ = true;
  Stop("e-stop from the host");
  return out;
}

CueingStep CueingSource::Step(double wall_s) {
  steps_ = DueSteps(wall_s);
  const double now_s = origin_s_ + static_cast<double>(periods_) * period_s_;
  // An e-stop is not left for the next period, even by a cycle with none due.
  if (std::optional<CueingStep> stop = EStop(now_s)) return *stop;
  CueingStep out;
  if (steps_ == 0) return out;  // woken early after a late cycle: no period is due
  out.time_s = now_s;
  out.input_sequence = input_.latest_sequence();
  const VehicleSample input = input_.At(now_s);
  const std::optional<CueCommand> command = input_.command();
  const bool live = input_.state(now_s) == VehicleInputState::kLive;
  const bool ask = !awaiting_reply_;
  switch (phase_) {
    case CueingPhase::kDisengaged:
      if (command == CueCommand::kEngage && live && ask) {
        out.request = CueRequest::kEngage;
        awaiting_reply_ = true;
        phase_ = CueingPhase::kEngaging;
        filter_->Reset();
        head_ = HeadCue{};
        return_from_ = Vector6::Zero();
        last_ = CueSetpoint{};
        last_.pose = neutral_;
        why_.clear();
        out.cue = Held();  // before the request: the planner has a cue as soon as it follows
      }
      break;
    case CueingPhase::kEngaging:
      out.cue = Held();
      if (planner_follows_) {
        phase_ = CueingPhase::kEngaged;
        engaged_s_ = now_s;
      }
      break;
    case CueingPhase::kEngaged:
      if (command == CueCommand::kDisengage) {
        phase_ = CueingPhase::kWashingOut;
        fade_out_s_ = now_s;
        gain_at_fade_out_ = RaisedCosine((now_s - engaged_s_) / config_.input.fade_s);
      } else if (command == CueCommand::kFreeze) {
        phase_ = CueingPhase::kFrozen;
        out.cue = Brake();
        break;
      }
      out.cue = Wash(input,
                     phase_ == CueingPhase::kEngaged ? RaisedCosine((now_s - engaged_s_) / config_.input.fade_s)
                                                     : gain_at_fade_out_,
                     now_s);
      break;
    case CueingPhase::kWashingOut: {
      const double faded = (now_s - fade_out_s_) / config_.input.fade_s;
      out.cue = Wash(input, gain_at_fade_out_ * (1.0 - RaisedCosine(faded)), now_s);
      const bool home = faded >= 1.0 && ReturnOffset(now_s).isZero(0.0) && HeadHome(head_, *out.cue);
      if ((home || now_s - fade_out_s_ > kWashoutTimeout_s) && ask) {
        out.request = CueRequest::kDisengage;
        awaiting_reply_ = true;
        phase_ = CueingPhase::kDisengaging;
      }
      break;
    }
    case CueingPhase::kFrozen:
      out.cue = Brake();
      if (command == CueCommand::kDisengage && out.cue->velocity.isZero(0.0) && ask) {
        out.request = CueRequest::kDisengage;
        awaiting_reply_ = true;
        phase_ = CueingPhase::kDisengaging;
      } else if (command == CueCommand::kEngage && live && out.cue->velocity.isZero(0.0)) {
        last_ = *out.cue;
        Resume(now_s);
      }
      break;
    case CueingPhase::kDisengaging: out.cue = Held(); break;
    case CueingPhase::kStopped:
      if (command == CueCommand::kDisengage && !planner_follows_) phase_ = CueingPhase::kDisengaged;
      break;
  }
  if (out.cue) last_ = *out.cue;
  return out;
}

}  // namespace edsp
