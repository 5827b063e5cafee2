#include "edsp/blindrig/blind_kinematics.h"

#include <cmath>

#include <Eigen/Geometry>

namespace edsp::blind {

namespace {

// Any unit vector perpendicular to `axis`: the reference direction of a
// joint's inner axis when both its angles are zero.
Vec3 Perpendicular(const Vec3& axis) {
  const Vec3 trial = std::abs(axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  return axis.cross(trial).normalized();
}

// A Hooke's joint with outer axis `outer` (fixed in the body it is mounted
// on) carrying a leg body whose axis is `leg` (unit, same coordinates).
// Reference: inner axis k0 ⟂ outer, leg axis w0 = outer × k0. The body's
// orientation is Rot(outer, α)·Rot(k0, β); it carries w0 onto
//   cos β·Rot(outer, α)·w0 + sin β·outer,
// so β = asin(leg·outer) and α follows from the component ⟂ outer. Returns
// the body-fixed inner axis Rot(outer, α)·k0, in the same coordinates.
Vec3 InnerAxisOfLegBody(const Vec3& outer, const Vec3& leg) {
  const Vec3 k0 = Perpendicular(outer);
  const Vec3 w0 = outer.cross(k0);
  const double alpha = std::atan2(-leg.dot(k0), leg.dot(w0));
  const Eigen::AngleAxisd cross_piece(alpha, outer);
  return cross_piece * k0;
}

// Leg i's vector for a pose whose rotation R = Rotation(q) is already known.
Vec3 LegVectorAt(const BlindGeometry& g, const Vec6& q, const Mat3& R, int leg) {
  return q.head<3>() + R * g.platform_joint.col(leg) - g.base_joint.col(leg);
}

}  // namespace

Mat3 Rotation(const Vec6& q) {
  return (Eigen::AngleAxisd(q(5), Vec3::UnitZ()) * Eigen::AngleAxisd(q(4), Vec3::UnitY()) *
          Eigen::AngleAxisd(q(3), Vec3::UnitX()))
      .toRotationMatrix();
}

Vec6 HomePose(const BlindGeometry& g) {
  Vec6 q = Vec6::Zero();
  q(2) = g.home_height_m;
  return q;
}

Vec3 LegVector(const BlindGeometry& g, const Vec6& q, int leg) { return LegVectorAt(g, q, Rotation(q), leg); }

Vec6 LegLengths(const BlindGeometry& g, const Vec6& q) {
  const Mat3 R = Rotation(q);
  Vec6 l;
  for (int i = 0; i < 6; ++i) l(i) = LegVectorAt(g, q, R, i).norm();
  return l;
}

Vec6 LegBodyTwist(const BlindGeometry& g, const Vec6& q) {
  const Mat3 R = Rotation(q);
  Vec6 twist;
  for (int i = 0; i < 6; ++i) {
    const Vec3 u = LegVectorAt(g, q, R, i).normalized();
    // Lower body: joint on the base, leg pointing up the leg.
    const Vec3 lower = InnerAxisOfLegBody(g.base_axis.col(i), u);
    // Upper body: joint on the platform, solved in {M}, leg pointing down.
    const Vec3 upper = R * InnerAxisOfLegBody(g.platform_axis.col(i), R.transpose() * -u);
    twist(i) = std::atan2(lower.cross(upper).dot(u), lower.dot(upper));
  }
  return twist;
}

}  // namespace edsp::blind
