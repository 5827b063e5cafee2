#include "edsp/kinematics/platform_model.h"

#include <cmath>
#include <utility>

namespace edsp {

PlatformModel::PlatformModel(PlatformConfig config) : config_(std::move(config)) {
  home_pose_.p_BoMo_B = Vector3(0.0, 0.0, config_.geometry.home_height_m);
  const LegSolution home = Solve(home_pose_);
  home_length_m_ = home.length_m;
  home_twist_rad_ = home.twist_rad;
}

LegSolution PlatformModel::Solve(const Pose& X_BM) const {
  const PlatformGeometry& g = config_.geometry;
  LegSolution s;
  s.R_BM = RotationFromRpy(X_BM.rpy_rad);
  s.r_MoPi_B.noalias() = s.R_BM * g.p_MoPi_M;
  s.leg_B = (s.r_MoPi_B - g.p_BoBi_B).colwise() + X_BM.p_BoMo_B;
  s.length_m = s.leg_B.colwise().norm().transpose();
  s.u_B = s.leg_B.array().rowwise() / s.length_m.transpose().array();
  s.jd_B.noalias() = s.R_BM * g.jd_M;
  s.twist_rad = SignedTwist(s.u_B, g.ja_B, s.jd_B);
  return s;
}

Vector6 PlatformModel::LegLengths(const Pose& X_BM) const { return Solve(X_BM).length_m; }

Matrix6 PlatformModel::LengthJacobian(const Pose& X_BM) const {
  Matrix6 J;
  Jacobians(X_BM, Solve(X_BM), &J, nullptr);
  return J;
}

Matrix6 PlatformModel::TwistJacobian(const Pose& X_BM) const {
  const LegSolution s = Solve(X_BM);
  Matrix6 J;
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = s.u_B.col(i);
    J.row(i) << u.transpose(), Vector3(s.r_MoPi_B.col(i)).cross(u).transpose();
  }
  return J;
}

double PlatformModel::PrScale() const { return config_.drive.pr_sign * config_.drive.lead_m / kTwoPi; }

Vector6 PlatformModel::PrLengthError(const LegSolution& legs, PrMode mode) const {
  Vector6 error;
  const double scale = PrScale();
  for (int i = 0; i < kNumLegs; ++i) {
    const double now = TwistAsModelled(legs.twist_rad(i), mode);
    const double home = TwistAsModelled(home_twist_rad_(i), mode);
    error(i) = scale * WrapAngle(now - home);
  }
  return error;
}

Vector6 PlatformModel::PrLengthError(const Pose& X_BM, PrMode mode) const { return PrLengthError(Solve(X_BM), mode); }

Matrix6 PlatformModel::PrLengthErrorJacobian(const Pose& X_BM) const {
  Matrix6 length_jacobian, pr_jacobian;
  Jacobians(X_BM, Solve(X_BM), &length_jacobian, &pr_jacobian);
  return pr_jacobian;
}

void PlatformModel::Jacobians(const Pose& X_BM, const LegSolution& s, Matrix6* length_jacobian,
                              Matrix6* pr_jacobian) const {
  const auto dR = RotationRpyDerivatives(X_BM.rpy_rad);
  const PlatformGeometry& g = config_.geometry;
  const double pr_scale = PrScale();
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = s.u_B.col(i);
    // ∂leg/∂q: translation columns are the unit axes, rotation columns dR·p.
    Matrix36 dleg;
    dleg.leftCols<3>().setIdentity();
    for (int k = 0; k < 3; ++k) dleg.col(3 + k) = dR[k] * g.p_MoPi_M.col(i);
    length_jacobian->row(i) = u.transpose() * dleg;
    if (pr_jacobian == nullptr) continue;
    // theta = atan2(y, x), y = (b×e)·u, x = b·e, b = u×ja, e = u×jd; the chain
    // rule runs through u (moved by every q) and jd (moved by the angles).
    const Vector3 ja = g.ja_B.col(i);
    const Vector3 jd = s.jd_B.col(i);
    const Vector3 b = u.cross(ja);
    const Vector3 e = u.cross(jd);
    const Vector3 bxe = b.cross(e);
    const double x = b.dot(e);
    const double y = bxe.dot(u);
    const double scale = pr_scale / (x * x + y * y);
    const Matrix36 du = (Matrix3::Identity() - u * u.transpose()) * dleg / s.length_m(i);
    for (int k = 0; k < 6; ++k) {
      const Vector3 duk = du.col(k);
      const Vector3 djd = k < 3 ? Vector3::Zero() : Vector3(dR[k - 3] * g.jd_M.col(i));
      const Vector3 db = duk.cross(ja);
      const Vector3 de = duk.cross(jd) + u.cross(djd);
      const double dx = db.dot(e) + b.dot(de);
      const double dy = (db.cross(e) + b.cross(de)).dot(u) + bxe.dot(duk);
      (*pr_jacobian)(i, k) = scale * (x * dy - y * dx);
    }
  }
}

Vector6 PlatformModel::CompensatedLengths(const Pose& X_BM, PrMode mode) const {
  const LegSolution s = Solve(X_BM);
  if (mode == PrMode::kNone) return s.length_m;
  return s.length_m - PrLengthError(s, mode);
}

Vector6 PlatformModel::EncoderLengths(const Pose& X_BM) const { return CompensatedLengths(X_BM, PrMode::kSigned); }

Vector3 PlatformModel::ObservationPoint(const Pose& X_BM) const { return PointInBase(X_BM, config_.p_MoA_M); }

}  // namespace edsp

namespace edsp {

double PlatformModel::MotorAngleFromLength(int leg, double length_m) const {
  return (length_m - home_length_m_(leg)) / config_.drive.lead_m * kTwoPi * config_.drive.gear_ratio;
}

double PlatformModel::LengthFromMotorAngle(int leg, double motor_angle_rad) const {
  return home_length_m_(leg) + motor_angle_rad / (kTwoPi * config_.drive.gear_ratio) * config_.drive.lead_m;
}

}  // namespace edsp
