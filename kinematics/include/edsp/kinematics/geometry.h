#pragma once
// Where the twelve Hooke's joints sit and how their outer axes point: the
// geometry every kinematic computation reads. Frames: {B} at the base centre,
// {M} at the platform centre (Drake-style monogram names).

#include <string>

#include "edsp/kinematics/types.h"

namespace edsp {

struct PlatformGeometry {
  Matrix36 p_BoBi_B = Matrix36::Zero();  // base joint centre i in {B}, m
  Matrix36 p_MoPi_M = Matrix36::Zero();  // platform joint centre i in {M}, m
  Matrix36 ja_B = Matrix36::Zero();      // base joint outer axis (fixed in {B}), unit
  Matrix36 jd_M = Matrix36::Zero();      // platform joint outer axis (fixed in {M}), unit
  double home_height_m = 0.0;            // z of {M} in {B} at the home pose
};

// The paper's platform (Huang et al. 2021), decoded as in docs/kinematics.md:
// Ra=1.2, Rb=1.5, da=0.2, db=0.3, H=1.511 m, axes of Eqs. (5)-(6).
struct Huang2021Dimensions {
  double platform_radius_m = 1.2;        // Ra
  double base_radius_m = 1.5;            // Rb
  double platform_pair_spacing_m = 0.2;  // da
  double base_pair_spacing_m = 0.3;      // db
  double home_height_m = 1.511;          // H
};
PlatformGeometry Huang2021Geometry(const Huang2021Dimensions& dims = {});

// Throws ConfigError naming `origin` and the offending key when the geometry
// is unusable: non-unit or non-finite axes, coincident joints, a layout whose
// legs cannot hold the platform (singular Jacobian at home), axes along a leg.
void ValidateGeometry(const PlatformGeometry& geometry, const std::string& origin);

}  // namespace edsp
