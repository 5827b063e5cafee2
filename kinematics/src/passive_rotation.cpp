#include "edsp/kinematics/passive_rotation.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

namespace edsp {

const char* PrModeName(PrMode mode) {
  switch (mode) {
    case PrMode::kNone: return "none";
    case PrMode::kUnsigned: return "unsigned";
    case PrMode::kSigned: return "signed";
    case PrMode::kAsin: return "asin";
  }
  return "invalid";
}

bool ParsePrMode(const char* text, PrMode* mode) {
  for (PrMode m : kPrModes) {
    const char digit[2] = {static_cast<char>('0' + static_cast<int>(m)), '\0'};
    if (std::strcmp(text, PrModeName(m)) == 0 || std::strcmp(text, digit) == 0) {
      *mode = m;
      return true;
    }
  }
  return false;
}

Vector6 SignedTwist(const Matrix36& u_B, const Matrix36& ja_B, const Matrix36& jd_B) {
  Vector6 twist;
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 u = u_B.col(i);
    const Vector3 jb = u.cross(ja_B.col(i));
    const Vector3 je = u.cross(jd_B.col(i));
    twist(i) = std::atan2(jb.cross(je).dot(u), jb.dot(je));
  }
  return twist;
}

double TwistAsModelled(double signed_twist_rad, PrMode mode) {
  switch (mode) {
    case PrMode::kNone: return 0.0;
    // jb, je ⟂ u, so |(jb×je)·u| = |jb×je| and atan2(|y|, x) = arccos(jb·je)
    // exactly, without arccos's loss of precision near 0 and π.
    case PrMode::kUnsigned: return std::abs(signed_twist_rad);
    case PrMode::kSigned: return signed_twist_rad;
    // genhexkins takes asin of ((u×(ja×u))ᵀ·(R·jd0×u)) = sin(theta).
    case PrMode::kAsin: return std::asin(std::sin(signed_twist_rad));
  }
  return 0.0;
}

double WrapAngle(double angle_rad) {
  const double wrapped = std::remainder(angle_rad, 2.0 * kPi);
  return wrapped <= -kPi ? wrapped + 2.0 * kPi : wrapped;
}

}  // namespace edsp
