#pragma once
// "x,y,z,roll,pitch,yaw" and "x,y,z" on command lines: finite numbers, SI units.

#include <string>

#include "edsp/kinematics/pose.h"

namespace edsp {

// Throws std::invalid_argument naming the text and the bad field.
Pose ParsePoseText(const std::string& text);
// "x,y,z": three finite numbers (m). Throws std::invalid_argument likewise.
Vector3 ParsePointText(const std::string& text);

}  // namespace edsp
