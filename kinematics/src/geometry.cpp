#include "edsp/kinematics/geometry.h"

#include <cmath>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "edsp/kinematics/config.h"

namespace edsp {

namespace {

double Deg(double degrees) { return degrees * kPi / 180.0; }

Vector3 OnCircle(double radius_m, double angle_rad) {
  return {radius_m * std::cos(angle_rad), radius_m * std::sin(angle_rad), 0.0};
}

// t(φ) = [−sin φ, cos φ, 0]: tangent of the circle at φ, which reproduces
// the paper's Eqs. (5)-(6).
Vector3 Tangent(double angle_deg) { return {-std::sin(Deg(angle_deg)), std::cos(Deg(angle_deg)), 0.0}; }

constexpr double kUnitTolerance = 1e-6;
constexpr double kMinJointSpacing_m = 1e-3;

void ValidateAxes(const Matrix36& axes, const std::string& origin, const char* key) {
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 axis = axes.col(i);
    if (!axis.allFinite() || std::abs(axis.norm() - 1.0) > kUnitTolerance) {
      throw ConfigError(fmt::format("{}: [geometry] {} row {} = [{}, {}, {}] must be a finite unit vector (norm {})",
                                    origin, key, i + 1, axis.x(), axis.y(), axis.z(), axis.norm()));
    }
  }
}

void ValidateJoints(const Matrix36& joints, const std::string& origin, const char* key) {
  if (!joints.allFinite()) {
    throw ConfigError(fmt::format("{}: [geometry] {} has a non-finite coordinate", origin, key));
  }
  for (int i = 0; i < kNumLegs; ++i) {
    for (int j = i + 1; j < kNumLegs; ++j) {
      const double spacing = (joints.col(i) - joints.col(j)).norm();
      if (spacing < kMinJointSpacing_m) {
        throw ConfigError(
            fmt::format("{}: [geometry] {} rows {} and {} are {} m apart: the six joints must be distinct "
                        "(at least {} m apart)",
                        origin, key, i + 1, j + 1, spacing, kMinJointSpacing_m));
      }
    }
  }
}

}  // namespace

PlatformGeometry Huang2021Geometry(const Huang2021Dimensions& d) {
  const double delta_b = std::asin(d.base_pair_spacing_m / (2.0 * d.base_radius_m));
  const double delta_a = std::asin(d.platform_pair_spacing_m / (2.0 * d.platform_radius_m));
  // Per leg: base pair angle and side (±δb), platform pair angle and side
  // (±δa), the base outer axis angle and the platform outer axis angle.
  struct Leg {
    double base_deg;
    double base_side;
    double platform_deg;
    double platform_side;
  };
  constexpr Leg kLegs[kNumLegs] = {{60, -1, 0, +1},    {300, +1, 0, -1},   {300, -1, 240, +1},
                                   {180, +1, 240, -1}, {180, -1, 120, +1}, {60, +1, 120, -1}};
  PlatformGeometry g;
  for (int i = 0; i < kNumLegs; ++i) {
    const Leg& leg = kLegs[i];
    g.p_BoBi_B.col(i) = OnCircle(d.base_radius_m, Deg(leg.base_deg) + leg.base_side * delta_b);
    g.p_MoPi_M.col(i) = OnCircle(d.platform_radius_m, Deg(leg.platform_deg) + leg.platform_side * delta_a);
    g.ja_B.col(i) = Tangent(leg.base_deg);
    g.jd_M.col(i) = Tangent(leg.platform_deg);
  }
  g.home_height_m = d.home_height_m;
  return g;
}

void ValidateGeometry(const PlatformGeometry& g, const std::string& origin) {
  ValidateJoints(g.p_BoBi_B, origin, "base_joints_m");
  ValidateJoints(g.p_MoPi_M, origin, "platform_joints_m");
  ValidateAxes(g.ja_B, origin, "base_axes");
  ValidateAxes(g.jd_M, origin, "platform_axes");
  if (!std::isfinite(g.home_height_m) || g.home_height_m <= 0.0) {
    throw ConfigError(
        fmt::format("{}: [geometry] home_height_m = {} must be a positive length", origin, g.home_height_m));
  }
  // At home: legs of non-zero length, not along their joint axes (a Hooke's
  // joint locks there), and a Jacobian that can hold the platform in all six
  // directions.
  Matrix6 J;
  for (int i = 0; i < kNumLegs; ++i) {
    const Vector3 p_B = g.p_MoPi_M.col(i) + Vector3(0, 0, g.home_height_m);
    const Vector3 leg = p_B - g.p_BoBi_B.col(i);
    if (leg.norm() < kMinJointSpacing_m) {
      throw ConfigError(fmt::format("{}: [geometry] leg {} has zero length at home", origin, i + 1));
    }
    const Vector3 u = leg.normalized();
    if (u.cross(g.ja_B.col(i)).norm() < 1e-3) {
      throw ConfigError(
          fmt::format("{}: [geometry] base_axes row {} is along leg {} at home: the Hooke's joint is locked", origin,
                      i + 1, i + 1));
    }
    if (u.cross(g.jd_M.col(i)).norm() < 1e-3) {
      throw ConfigError(
          fmt::format("{}: [geometry] platform_axes row {} is along leg {} at home: the Hooke's joint is "
                      "locked",
                      origin, i + 1, i + 1));
    }
    J.row(i) << u.transpose(), g.p_MoPi_M.col(i).cross(u).transpose();
  }
  Eigen::JacobiSVD<Matrix6> svd(J);
  const auto& sv = svd.singularValues();
  if (!(sv(5) > 1e-6 * sv(0))) {
    throw ConfigError(
        fmt::format("{}: [geometry] degenerate layout: the legs cannot constrain all six degrees of freedom "
                    "at home (Jacobian singular values {} .. {})",
                    origin, sv(0), sv(5)));
  }
}

}  // namespace edsp
