#pragma once
// "x,y,z,roll,pitch,yaw" on command lines: six finite numbers, SI units.

#include <string>

#include "edsp/kinematics/pose.h"

namespace edsp {

// Throws std::invalid_argument naming the text and the bad field.
Pose ParsePoseText(const std::string& text);

}  // namespace edsp
