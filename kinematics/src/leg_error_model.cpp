#include "edsp/kinematics/leg_error_model.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "edsp/kinematics/platform_loads.h"

namespace edsp::calibration {

namespace {

Eigen::Matrix<double, 6, 4> LoadColumns(const PlatformModel& model, const Pose& pose, const Vector3& accel,
                                        const LegErrorOptions& o) {
  const Vector3 coms[4] = {Vector3::Zero(), Vector3::UnitX(), Vector3::UnitY(), Vector3::UnitZ()};
  Eigen::Matrix<double, 6, 4> F;
  for (int c = 0; c < 4; ++c) {
    // Absolute, not from home: a rig homed by its encoders sits lower at home too.
    F.col(c) = LegForces(model, pose, accel, 1.0, coms[c], o.gravity_B_m_s2);
  }
  for (int c = 1; c < 4; ++c) F.col(c) -= F.col(0);
  return F;
}

}  // namespace

LegErrorTracker::LegErrorTracker(PlatformModel model, LegErrorOptions options)
    : model_(std::move(model)), options_(options), driven_(-options.backlash_width_m * Vector6::Ones()) {
  if (options_.structural_mode_hz > 0.0) mode_.emplace(options_.structural_mode_hz, options_.structural_mode_damping);
}

LegErrorState LegErrorTracker::Advance(const LegErrorInputs& in) {
  LegErrorState s;
  s.legs = model_.Solve(in.pose);
  s.stroke = in.command_m - model_.home_length_m();
  s.velocity = in.velocity;
  s.accel = in.accel;
  s.jerk = in.jerk;
  // The play sits between the motor and the screw: the motor's own motion
  // drives it, lag and all.
  const double w = options_.backlash_width_m;
  const Vector6 motor = in.motor_m - model_.home_length_m();
  for (int i = 0; i < 6; ++i) {
    const double x = motor(i);
    if (x - driven_(i) > w) driven_(i) = x - w;
    if (driven_(i) > x) driven_(i) = x;
    s.play(i) = 1.0 - (x - driven_(i)) / w;
  }
  if (mode_) s.sway = mode_->Advance(in.time_s - last_time_s_, in.point_accel_B_m_s2);
  if (!first_) {
    const double dt = std::max(0.0, in.time_s - last_time_s_);
    const double cooling = std::exp(-dt / options_.thermal_time_constant_s);
    heat_ = heat_ * cooling + (s.stroke - last_stroke_).cwiseAbs();
    warm_ = warm_ * cooling + options_.thermal_time_constant_s * (1.0 - cooling);
  }
  first_ = false;
  last_time_s_ = in.time_s;
  last_stroke_ = s.stroke;
  s.heat = heat_;
  s.warm = warm_;
  s.pr_signed = model_.PrLengthError(s.legs, PrMode::kSigned);
  s.compensation = s.legs.length_m - in.command_m;
  s.load = LoadColumns(model_, in.pose, in.platform_accel_B_m_s2, options_);
  s.translation = mode_ ? TranslationToLegs(model_, in.pose) : Eigen::Matrix<double, 6, 3>::Zero();
  return s;
}

Eigen::Matrix<double, 6, 3> TranslationToLegs(const PlatformModel& model, const Pose& pose) {
  return (model.LengthJacobian(pose) - model.PrLengthErrorJacobian(pose)).leftCols<3>();
}

Matrix3 Skew(const Vector3& v) {
  Matrix3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

bool PointSensitivityAt(const PlatformModel& model, const Pose& pose, PointSensitivity* out) {
  const Matrix6 M = model.LengthJacobian(pose) - model.PrLengthErrorJacobian(pose);
  const Eigen::FullPivLU<Matrix6> lu(M);
  if (!pose.IsFinite() || !lu.isInvertible()) return false;
  // ∂A/∂q by central differences (A is a smooth, cheap function of the pose).
  const Vector6 q = pose.ToVector();
  Eigen::Matrix<double, 3, 6> J;
  constexpr double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Vector6 plus = q, minus = q;
    plus(k) += h;
    minus(k) -= h;
    J.col(k) =
        (model.ObservationPoint(Pose::FromVector(plus)) - model.ObservationPoint(Pose::FromVector(minus))) / (2.0 * h);
  }
  out->point = model.ObservationPoint(pose);
  out->per_leg = J * lu.inverse();
  return true;
}

Eigen::MatrixXd LegErrorBasis(Effect effect, const LegErrorState& s, const PlatformModel& model) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, ParameterCount(effect));
  const double lead = model.config().drive.lead_m;
  switch (effect) {
    case Effect::kPassiveRotation:
      B.col(0) = s.pr_signed;
      B.col(1) = s.compensation;
      break;
    case Effect::kLegOffset: B = Eigen::MatrixXd::Identity(6, 6); break;
    case Effect::kJointPosition:
      for (int i = 0; i < 6; ++i) {
        // A base joint moved by δb shortens the geometric leg by û·δb, so the
        // drive length reaches a pose whose nominal length is longer: +û·δb.
        const Vector3 u = s.legs.u_B.col(i);
        B.block<1, 3>(i, 3 * i) = u.transpose();
        B.block<1, 3>(i, 18 + 3 * i) = -(s.legs.R_BM.transpose() * u).transpose();
      }
      break;
    case Effect::kLeadError:
      for (int i = 0; i < 6; ++i) B(i, i) = s.stroke(i);
      break;
    case Effect::kPeriodicLeadError:
      for (int i = 0; i < 6; ++i) {
        const double phi = kTwoPi * s.stroke(i) / lead;
        B(i, 2 * i) = std::sin(phi);
        B(i, 2 * i + 1) = std::cos(phi) - 1.0;
      }
      break;
    case Effect::kBacklash:
      // Share of the play taken up on the retracting side (0 after extending).
      for (int i = 0; i < 6; ++i) B(i, i) = s.play(i);
      break;
    case Effect::kServoLag:
      for (int i = 0; i < 6; ++i) {
        B(i, i) = -s.velocity(i);
        B(i, 6 + i) = -s.accel(i);
      }
      B.col(12) = -s.jerk;
      break;
    case Effect::kCompliance:
      // Δl_i = −F_i(m, m·c)/k_i: each leg its own stiffness for the weight
      // and inertia of the mass, one mean stiffness for the c.o.m.'s moments.
      for (int i = 0; i < 6; ++i) B(i, i) = -s.load(i, 0);
      B.rightCols(3) = -s.load.rightCols(3);
      break;
    case Effect::kThermalDrift:
      // A screw grows α·ΔT over the part between its bearing and the nut: a
      // fixed length plus the stroke. ΔT is driven by the leg's own travel
      // (friction in the nut) and by time under power (the motor's heat),
      // both cooling with one time constant.
      B.col(0) = s.heat;
      B.col(1) = s.heat.cwiseProduct(s.stroke);
      B.col(2).setConstant(s.warm);
      B.col(3) = s.warm * s.stroke;
      break;
    case Effect::kStructuralResonance:
      // A sways by g ⊙ x relative to the platform: the legs that would move
      // the platform (and A with it) by as much.
      for (int axis = 0; axis < 3; ++axis) B.col(axis) = s.translation.col(axis) * s.sway(axis);
      break;
  }
  return B;
}

}  // namespace edsp::calibration
