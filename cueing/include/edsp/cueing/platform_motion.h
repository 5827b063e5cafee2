#pragma once
// What a rider on the platform feels: the specific force and angular
// velocity at the head, in the head frame (the platform's {M}), from the
// platform's poses sampled at one period (commanded setpoints, or the
// rig's measured truth). Central differences: the head's acceleration from
// its positions, the angular velocity from successive rotations
// (R(k+1)·R(k−1)ᵀ as an angle-axis over 2T), so the Euler angles' rates
// are never confused with the body's.

#include <vector>

#include "edsp/cueing/vehicle_motion.h"
#include "edsp/kinematics/pose.h"

namespace edsp {

// One VehicleSample per pose (the first and last take their neighbours'
// values); sample k at t = k·period_s. Needs at least 3 poses.
VehicleSeries PlatformMotionAtHead(const std::vector<Pose>& poses, double period_s, const Vector3& head_in_platform_m);

}  // namespace edsp
