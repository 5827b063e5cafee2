#pragma once
// The platform pose q = [x y z roll pitch yaw] (m, rad) and its rotation
// R_BM = Rz(yaw)·Ry(pitch)·Rx(roll) (the paper's Eq. 3).

#include <array>
#include <string>

#include "edsp/kinematics/types.h"

namespace edsp {

struct Pose {
  Vector3 p_BoMo_B = Vector3::Zero();  // platform centre in {B}, m
  Vector3 rpy_rad = Vector3::Zero();   // roll, pitch, yaw, rad

  static Pose FromVector(const Vector6& q);
  Vector6 ToVector() const;
  bool IsFinite() const;
};

// R_BM for the given roll, pitch, yaw.
Matrix3 RotationFromRpy(const Vector3& rpy_rad);

// The roll, pitch, yaw of R_BM (pitch in [−π/2, π/2]; the inverse of
// RotationFromRpy away from pitch ±π/2, where roll and yaw are one axis).
Vector3 RpyFromRotation(const Matrix3& R_BM);

// dR_BM/droll, dR_BM/dpitch, dR_BM/dyaw at the given angles.
std::array<Matrix3, 3> RotationRpyDerivatives(const Vector3& rpy_rad);

// Position of a point given in {M}, expressed in {B}, for the pose.
Vector3 PointInBase(const Pose& X_BM, const Vector3& p_MoQ_M);

// "x=..., y=..., ..." for error messages.
std::string DescribePose(const Pose& pose);

}  // namespace edsp
