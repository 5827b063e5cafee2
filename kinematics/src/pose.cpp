#include "edsp/kinematics/pose.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace edsp {

Pose Pose::FromVector(const Vector6& q) {
  Pose pose;
  pose.p_BoMo_B = q.head<3>();
  pose.rpy_rad = q.tail<3>();
  return pose;
}

Vector6 Pose::ToVector() const {
  Vector6 q;
  q << p_BoMo_B, rpy_rad;
  return q;
}

bool Pose::IsFinite() const { return p_BoMo_B.allFinite() && rpy_rad.allFinite(); }

namespace {

struct AxisRotations {
  Matrix3 Rx, Ry, Rz;
};

AxisRotations ElementaryRotations(const Vector3& rpy_rad) {
  const double cr = std::cos(rpy_rad.x()), sr = std::sin(rpy_rad.x());
  const double cp = std::cos(rpy_rad.y()), sp = std::sin(rpy_rad.y());
  const double cy = std::cos(rpy_rad.z()), sy = std::sin(rpy_rad.z());
  AxisRotations r;
  r.Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  r.Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  r.Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return r;
}

Matrix3 Hat(const Vector3& w) {
  Matrix3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

}  // namespace

Matrix3 RotationFromRpy(const Vector3& rpy_rad) {
  // Written out (Eq. 3) rather than multiplied: this is on every hot path.
  const double cr = std::cos(rpy_rad.x()), sr = std::sin(rpy_rad.x());
  const double cp = std::cos(rpy_rad.y()), sp = std::sin(rpy_rad.y());
  const double cy = std::cos(rpy_rad.z()), sy = std::sin(rpy_rad.z());
  Matrix3 R;
  R << cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy,  //
      cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy,   //
      -sp, sr * cp, cr * cp;
  return R;
}

Vector3 RpyFromRotation(const Matrix3& R) {
  // R = Rz(yaw)·Ry(pitch)·Rx(roll): R(2,0) = −sin(pitch), R(2,1)/R(2,2) = tan(roll), R(1,0)/R(0,0) = tan(yaw).
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return Vector3(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}

std::array<Matrix3, 3> RotationRpyDerivatives(const Vector3& rpy_rad) {
  const AxisRotations r = ElementaryRotations(rpy_rad);
  // d(Rz Ry Rx)/dθ inserts the generator of the rotated axis in place.
  return {r.Rz * r.Ry * r.Rx * Hat(Vector3::UnitX()), r.Rz * r.Ry * Hat(Vector3::UnitY()) * r.Rx,
          Hat(Vector3::UnitZ()) * r.Rz * r.Ry * r.Rx};
}

Vector3 PointInBase(const Pose& X_BM, const Vector3& p_MoQ_M) {
  return RotationFromRpy(X_BM.rpy_rad) * p_MoQ_M + X_BM.p_BoMo_B;
}

std::string DescribePose(const Pose& pose) {
  return fmt::format("x={} y={} z={} m, roll={} pitch={} yaw={} rad", pose.p_BoMo_B.x(), pose.p_BoMo_B.y(),
                     pose.p_BoMo_B.z(), pose.rpy_rad.x(), pose.rpy_rad.y(), pose.rpy_rad.z());
}

}  // namespace edsp
