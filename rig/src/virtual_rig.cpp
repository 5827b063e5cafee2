#include "edsp/rig/virtual_rig.h"

#include <algorithm>
#include <cmath>

#include "edsp/kinematics/finite_difference.h"
#include "edsp/kinematics/platform_loads.h"

namespace edsp {

RigParameters IdealRig(const PlatformConfig& nominal) {
  RigParameters p;
  p.nominal = nominal;
  p.tracker.X_TB = Pose{};
  return p;
}

namespace {

// The true geometry, with the lead and sign the screws' PR really has.
PlatformConfig PrConfig(const RigParameters& p) {
  PlatformConfig c = TrueConfig(p.nominal, p.effects);
  const RigEffects::PassiveRotation& pr = p.effects.passive_rotation;
  if (pr.enabled) {
    if (pr.pr_sign != 0) c.drive.pr_sign = pr.pr_sign;
    if (pr.pr_lead_m > 0.0) c.drive.lead_m = pr.pr_lead_m;
  }
  return c;
}

}  // namespace

VirtualRig::VirtualRig(RigParameters parameters)
    : parameters_(std::move(parameters)),
      model_(PrConfig(parameters_)),
      pose_(model_.home_pose()),
      rng_(parameters_.tracker.seed) {
  fk_options_.with_pr =
      !(parameters_.effects.passive_rotation.enabled && parameters_.effects.passive_rotation.pr_sign == 0);
  // The legs' zero is the nominal home length (where the rig was homed).
  const PlatformModel nominal(parameters_.nominal);
  const LegSolution home = nominal.Solve(nominal.home_pose());
  for (int i = 0; i < kNumLegs; ++i) {
    transmissions_.emplace_back(i, home.length_m(i), parameters_.nominal.drive, parameters_.effects);
    lengths_(i) = transmissions_.back().Length(0.0);
  }
  // The platform starts where those legs put it (sagging under its weight).
  rigid_pose_ = rigid_previous_ = pose_;
  const RigEffects& e = parameters_.effects;
  loaded_ = e.compliance.enabled || (e.servo_lag.enabled && e.servo_lag.load_mass_kg > 0.0);
  if (e.servo_lag.enabled && loaded_) {
    // Each motor moves about a sixth of the platform along its leg.
    load_mass_per_leg_kg_ = (e.compliance.enabled ? e.compliance.total_mass_kg() : e.servo_lag.load_mass_kg) / 6.0;
  }
  Vector6 lengths = lengths_;
  if (loaded_) UpdateLoads(0.0);
  if (e.compliance.enabled) Deflect(&lengths);
  const FkResult fk = SolveForward(model_, lengths, pose_, fk_options_);
  if (fk.ok()) pose_ = fk.pose;
  // Critically damped position loop at the requested bandwidth, tuned on
  // the inertia the motor moves, the payload's included: a drive is
  // commissioned with its load on (tuned on the bare motor, an 800 kg
  // platform would cut the loop's bandwidth by 40% and lag every motion).
  const RigEffects::ServoLag& servo = parameters_.effects.servo_lag;
  const double wn = kTwoPi * servo.bandwidth_hz;
  kp_ = MovedInertia() * wn * wn;
  kd_ = 2.0 * MovedInertia() * wn;
  if (e.structural_resonance.enabled)
    mode_.emplace(e.structural_resonance.frequency_hz, e.structural_resonance.damping);
  ki_ = servo.integral_time_s > 0.0 ? kp_ / servo.integral_time_s : 0.0;
  // An integrating drive has been holding the platform before the run: its
  // integral already carries the weight (as after enabling and settling).
  if (servo.enabled && ki_ > 0.0) {
    for (int i = 0; i < kNumLegs; ++i) {
      integral_[static_cast<std::size_t>(i)] = static_leg_forces_(i) * ScrewRatio() / ki_;
    }
  }
}

void VirtualRig::SetTarget(const DriveSetpoint& setpoint, bool enabled) {
  target_ = setpoint;
  enabled_ = enabled;
  if (!enabled) faulted_.fill(false);  // disabling the drives resets their faults
  since_command_s_ = 0.0;
  since_target_s_ = 0.0;
}

bool VirtualRig::RestoreDrives(const std::array<double, 6>& motor_angle_rad) {
  for (int i = 0; i < kNumLegs; ++i) {
    angle_[i] = motor_angle_rad[i];
    velocity_[i] = 0.0;
    target_.motor_angle_rad[i] = motor_angle_rad[i];
    target_.motor_velocity_rad_s[i] = 0.0;
    lengths_(i) = transmissions_[static_cast<std::size_t>(i)].Length(angle_[i]);
  }
  enabled_ = false;
  const FkResult fk = SolveForward(model_, lengths_, pose_, fk_options_);
  if (!fk.ok()) return false;
  pose_ = rigid_pose_ = rigid_previous_ = fk.pose;
  rigid_history_ = 0;
  return true;
}

bool VirtualRig::any_drive_faulted() const {
  return std::any_of(faulted_.begin(), faulted_.end(), [](bool f) { return f; });
}

bool VirtualRig::watchdog_tripped() const {
  return enabled_ && since_command_s_ > parameters_.watchdog.timeout_s + 1e-9;  // dt sums are inexact
}

void VirtualRig::StepIdeal(int i, double dt) {
  if (enabled_) {
    // On the (interpolated) target at the end of the step.
    target_.motor_angle_rad[i] += dt * target_.motor_velocity_rad_s[i];
    angle_[i] = target_.motor_angle_rad[i];
    velocity_[i] = target_.motor_velocity_rad_s[i];
  } else {
    velocity_[i] = 0.0;
  }
}

namespace {

// One step of a motor with dry friction: it sticks while the other torques
// cannot overcome `coulomb`, and a moving motor that friction would reverse
// stops instead (a discrete Coulomb model that needs no tiny time step).
double VelocityWithCoulomb(double v, double net_torque, double coulomb, double inertia, double dt) {
  if (coulomb <= 0.0) return v + dt * net_torque / inertia;
  if (v == 0.0 && std::abs(net_torque) <= coulomb) return 0.0;
  const double direction = v != 0.0 ? (v > 0.0 ? 1.0 : -1.0) : (net_torque > 0.0 ? 1.0 : -1.0);
  const double next = v + dt * (net_torque - coulomb * direction) / inertia;
  return v != 0.0 && next * v < 0.0 ? 0.0 : next;
}

}  // namespace

double VirtualRig::ScrewRatio() const {
  return parameters_.nominal.drive.lead_m /
         (kTwoPi * parameters_.nominal.drive.gear_ratio * parameters_.effects.servo_lag.screw_efficiency);
}

double VirtualRig::MovedInertia() const {
  const RigEffects::ServoLag& s = parameters_.effects.servo_lag;
  const double screw = ScrewRatio();
  return s.inertia_kg_m2 + load_mass_per_leg_kg_ * screw * screw * s.screw_efficiency;
}

void VirtualRig::StepServo(int i, double dt) {
  const RigEffects::ServoLag& s = parameters_.effects.servo_lag;
  const auto leg = static_cast<std::size_t>(i);
  if (!enabled_ || faulted_[leg]) {
    // A disabled or faulted drive's holding brake: the platform's weight
    // cannot back-drive the screw while nobody commands it.
    velocity_[i] = 0.0;
    target_.motor_angle_rad[i] += dt * target_.motor_velocity_rad_s[i];
    return;
  }
  const double error = target_.motor_angle_rad[i] - angle_[i];
  if (s.following_error_window_m > 0.0 &&
      std::abs(error) * ScrewRatio() * s.screw_efficiency > s.following_error_window_m) {
    faulted_[leg] = true;
    velocity_[i] = 0.0;
    return;
  }
  const double unclamped = kp_ * error + kd_ * (target_.motor_velocity_rad_s[i] - velocity_[i]) +
                           ki_ * (integral_[leg] + error * dt) +
                           s.viscous_N_m_s * target_.motor_velocity_rad_s[i];  // friction feed-forward
  const double torque = std::clamp(unclamped, -s.torque_limit_N_m, s.torque_limit_N_m);
  if (torque == unclamped) integral_[leg] += error * dt;  // no wind-up against the current limit
  // The platform's weight on this leg, at the motor (it resists extension),
  // and its mass as inertia the motor accelerates with it: in the motor's
  // own equation, not as a force a step late, which would make a loop.
  const double load = static_leg_forces_(i) * ScrewRatio();
  // Semi-implicit Euler: stable for the stiff loop at the drive's rate.
  velocity_[i] = VelocityWithCoulomb(velocity_[i], torque - s.viscous_N_m_s * velocity_[i] - load, s.coulomb_N_m,
                                     MovedInertia(), dt);
  angle_[i] += dt * velocity_[i];
  // Between bridge cycles the drive interpolates its target along the
  // velocity feed-forward, as a real drive's interpolator does.
  target_.motor_angle_rad[i] += dt * target_.motor_velocity_rad_s[i];
}

bool VirtualRig::Advance(double dt_s) {
  const bool servo = parameters_.effects.servo_lag.enabled;
  const double loop_dt = 1.0 / parameters_.effects.servo_lag.loop_rate_hz;
  const int steps = std::max(1, static_cast<int>(std::lround(dt_s / loop_dt)));
  // No new target for a few cycles: stop interpolating, hold at rest.
  if (since_target_s_ >= parameters_.watchdog.interpolation_horizon_s - 1e-9) {
    target_.motor_velocity_rad_s.fill(0.0);
  }
  since_command_s_ += dt_s;
  since_target_s_ += dt_s;
  for (int k = 0; k < steps; ++k) {
    for (int i = 0; i < kNumLegs; ++i) {
      if (servo)
        StepServo(i, dt_s / steps);
      else
        StepIdeal(i, dt_s / steps);
      // The drive train at the loop rate: backlash sees every reversal.
      lengths_(i) = transmissions_[static_cast<std::size_t>(i)].Length(angle_[i], dt_s / steps);
    }
  }
  time_s_ += dt_s;
  Vector6 lengths = lengths_;
  if (loaded_ && !UpdateLoads(dt_s)) return false;
  if (parameters_.effects.compliance.enabled) Deflect(&lengths);
  // Forward kinematics in the rig's own geometry adds each screw's true
  // signed PR to the drive-train lengths.
  const FkResult fk = SolveForward(model_, lengths, pose_, fk_options_);
  if (!fk.ok()) return false;
  pose_ = fk.pose;
  if (mode_) Sway(dt_s);
  return true;
}

void VirtualRig::Sway(double dt_s) {
  // A's acceleration on the platform, from its last three places (the one a
  // step ago, unequal steps allowed): what the mount it sits on feels.
  const Vector3 point = model_.ObservationPoint(pose_);
  Vector3 accel = Vector3::Zero();
  const double h1 = last_dt_s_, h2 = dt_s;
  if (point_steps_ >= 2 && h1 > 0.0 && h2 > 0.0) {
    accel = SecondDerivative<Vector3>(point_history_[1], point_history_[0], point, h1, h2);
  }
  point_history_[1] = point_history_[0];
  point_history_[0] = point;
  last_dt_s_ = dt_s;
  ++point_steps_;
  sway_ = parameters_.effects.structural_resonance.gain.cwiseProduct(mode_->Advance(dt_s, accel));
}

Vector3 VirtualRig::ObservedPoint() const { return model_.ObservationPoint(pose_) + sway_; }

bool VirtualRig::UpdateLoads(double dt_s) {
  // The loads come from the rigid platform's motion (the drive trains'), so
  // the deflections never feed back into the acceleration that causes them.
  const FkResult rigid = SolveForward(model_, lengths_, rigid_pose_, fk_options_);
  if (!rigid.ok()) return false;
  Vector3 accel = Vector3::Zero();
  if (rigid_history_ >= 2 && dt_s > 0.0) {
    accel = (rigid.pose.p_BoMo_B - 2.0 * rigid_pose_.p_BoMo_B + rigid_previous_.p_BoMo_B) / (dt_s * dt_s);
  }
  rigid_previous_ = rigid_pose_;
  rigid_pose_ = rigid.pose;
  ++rigid_history_;
  const RigEffects& e = parameters_.effects;
  const bool platform = e.compliance.enabled;
  const double mass = platform ? e.compliance.total_mass_kg() : e.servo_lag.load_mass_kg;
  const Vector3 com = platform ? e.compliance.total_com_m() : Vector3::Zero();
  leg_forces_ = LegForces(model_, rigid.pose, accel, mass, com, e.compliance.gravity_m_s2);
  static_leg_forces_ = LegForces(model_, rigid.pose, Vector3::Zero(), mass, com, e.compliance.gravity_m_s2);
  return true;
}

void VirtualRig::Deflect(Vector6* lengths) const {
  const RigEffects::Compliance& c = parameters_.effects.compliance;
  for (int i = 0; i < kNumLegs; ++i) (*lengths)(i) -= leg_forces_(i) / c.stiffness_N_m[static_cast<std::size_t>(i)];
}

DriveFeedback VirtualRig::Feedback() const {
  DriveFeedback f;
  for (int i = 0; i < kNumLegs; ++i) {
    f.motor_angle_rad[i] = angle_[i];
    f.motor_velocity_rad_s[i] = velocity_[i];
    f.status[i] = !enabled_                               ? DriveStatus::kDisabled
                  : faulted_[static_cast<std::size_t>(i)] ? DriveStatus::kFault
                  : watchdog_tripped()                    ? DriveStatus::kHolding
                                                          : DriveStatus::kEnabled;
  }
  return f;
}

rig_truth_t VirtualRig::Truth(std::int64_t utime) {
  rig_truth_t t{};
  t.utime = utime;
  t.seq = ++truth_seq_;
  const LegSolution legs = model_.Solve(pose_);
  const Vector6 q = pose_.ToVector();
  const Vector3 a = ObservedPoint();
  for (int i = 0; i < kNumLegs; ++i) {
    t.pose[i] = q(i);
    t.leg_length_m[i] = legs.length_m(i);
    t.twist_rad[i] = legs.twist_rad(i);
  }
  for (int k = 0; k < 3; ++k) t.observation_point_m[k] = a(k);
  return t;
}

bool VirtualRig::TrackerSample(std::int64_t utime, tracker_point_t* point) {
  if (time_s_ + 1e-9 < next_tracker_s_) return false;
  next_tracker_s_ += 1.0 / parameters_.tracker.rate_hz;
  const TrackerParameters& tp = parameters_.tracker;
  Vector3 p_T = PointInBase(tp.X_TB, ObservedPoint());
  std::normal_distribution<double> noise(0.0, tp.noise_sigma_m);
  if (tp.noise_sigma_m > 0.0) {
    for (int k = 0; k < 3; ++k) p_T(k) += noise(rng_);
  }
  *point = tracker_point_t{};
  point->utime = utime;
  point->seq = ++tracker_seq_;
  for (int k = 0; k < 3; ++k) point->point_m[k] = p_T(k);
  point->sigma_m = tp.noise_sigma_m;
  point->valid = true;
  return true;
}

bool InProcessRigBackend::Configure(const PlatformConfig&, std::string*) {
  state_ = BackendState::kInactive;
  return true;
}

bool InProcessRigBackend::Activate(std::string* error) {
  if (state_ == BackendState::kUnconfigured) {
    *error = "activate before configure";
    return false;
  }
  state_ = BackendState::kActive;
  return true;
}

void InProcessRigBackend::Deactivate() {
  rig_->SetTarget(DriveSetpoint{}, false);
  state_ = BackendState::kInactive;
}

bool InProcessRigBackend::Read(std::int64_t, DriveFeedback* feedback) {
  *feedback = rig_->Feedback();
  return !rig_->any_drive_faulted();  // a braked drive: the bridge stops the others
}

bool InProcessRigBackend::Reset(std::string*) {
  // Disabling the drives resets their faults; the next write enables them.
  DriveSetpoint here;
  const DriveFeedback now = rig_->Feedback();
  here.motor_angle_rad = now.motor_angle_rad;
  rig_->SetTarget(here, false);
  return true;
}

bool InProcessRigBackend::Write(std::int64_t, const DriveSetpoint& setpoint) {
  if (state_ != BackendState::kActive) return false;  // motion only while active
  rig_->SetTarget(setpoint, true);
  return true;
}

}  // namespace edsp
