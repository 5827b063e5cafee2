#pragma once
// A sampled pose path played through the whole stack offline (the
// kinematics node, the bridge and the virtual rig with its effects, on
// StackSimulation's clock): where the platform really went, sample by
// sample. What a rider on the rig feels is the drives' lag and the legs'
// compliance on top of the commands; this is how it is measured without a
// rig (docs/cueing.md scores motion cueing on it).

#include <vector>

#include "edsp/kinematics/pose.h"
#include "edsp/rig/rig_effects.h"

namespace edsp {

// `poses` one per `period_s` (the stack's cycle, 1 ms), from the home pose
// (the rig starts there); the true pose at each sample's instant. Throws
// std::invalid_argument if a pose leaves the workspace or the period is not
// the stack's cycle, std::runtime_error if the stack refused a setpoint.
std::vector<Pose> PlayPosesThroughTheStack(const PlatformConfig& nominal, const RigEffects& effects,
                                           const std::vector<Pose>& poses, double period_s);

}  // namespace edsp
