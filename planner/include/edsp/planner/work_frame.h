#pragma once
// Where a move's pose is given: a work frame W (a pose in {B}) and the
// pivot c (a point of {M}). A pose (t, r) in W about c means
//   X_BM = X_BW · Trans(t) · Trans(c) · R(r) · Trans(−c),
// so rotations turn about the pivot, which sits at t + c in W whatever r
// is; with c = 0 and W = {B} it is the pose of {M} in {B}, as on
// EDSP_SETPOINT.

#include <string>

#include <Eigen/Geometry>

#include "edsp/kinematics/pose.h"

namespace edsp {

using Transform = Eigen::Isometry3d;

Transform TransformOf(const Pose& pose);
Pose PoseOf(const Transform& X);

// A pose expressed in a work frame about a pivot: the pivot's position t
// (less c, as above) and the rotation R.
struct FramedPose {
  Vector3 t = Vector3::Zero();
  Matrix3 R = Matrix3::Identity();
};

struct WorkFrame {
  std::string name = "base";
  Transform X_BW = Transform::Identity();
};

// X_BM of `p` in `frame` about `pivot_M`.
Transform PlatformPose(const WorkFrame& frame, const Vector3& pivot_M, const FramedPose& p);
// The inverse: `X_BM` as a pose in `frame` about `pivot_M`.
FramedPose InFrame(const WorkFrame& frame, const Vector3& pivot_M, const Transform& X_BM);
// (x y z roll pitch yaw) → (t, R(roll, pitch, yaw)).
FramedPose FramedPoseOf(const Vector6& q);

}  // namespace edsp
