#include "edsp/planner/work_frame.h"

namespace edsp {

Transform TransformOf(const Pose& pose) {
  Transform X = Transform::Identity();
  X.linear() = RotationFromRpy(pose.rpy_rad);
  X.translation() = pose.p_BoMo_B;
  return X;
}

Pose PoseOf(const Transform& X) {
  Pose pose;
  pose.p_BoMo_B = X.translation();
  pose.rpy_rad = RpyFromRotation(X.linear());
  return pose;
}

Transform PlatformPose(const WorkFrame& frame, const Vector3& c, const FramedPose& p) {
  Transform X_WM = Transform::Identity();
  X_WM.linear() = p.R;
  X_WM.translation() = p.t + c - p.R * c;
  return frame.X_BW * X_WM;
}

FramedPose InFrame(const WorkFrame& frame, const Vector3& c, const Transform& X_BM) {
  const Transform X_WM = frame.X_BW.inverse() * X_BM;
  FramedPose p;
  p.R = X_WM.linear();
  p.t = X_WM.translation() - c + p.R * c;
  return p;
}

FramedPose FramedPoseOf(const Vector6& q) { return {q.head<3>(), RotationFromRpy(q.tail<3>())}; }

}  // namespace edsp
