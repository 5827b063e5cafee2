#pragma once
// Fixed-size Eigen aliases shared by the kinematics library. Per-leg data is
// stored column-per-leg (3x6) or as a 6-vector, leg 1 first.

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace edsp {

inline constexpr int kNumLegs = 6;
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

using Vector3 = Eigen::Vector3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix3 = Eigen::Matrix3d;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Matrix36 = Eigen::Matrix<double, 3, 6>;  // one column per leg

}  // namespace edsp
