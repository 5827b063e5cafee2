#pragma once
// Reproducible random poses inside the workspace, for property tests.

#include <random>
#include <vector>

#include "edsp/kinematics/workspace.h"

namespace edsp::test_support {

// Uniform in ±0.5 m, ±30° about home (the paper's ranges), rejecting poses the
// workspace checks refuse.
inline std::vector<Pose> RandomWorkspacePoses(const PlatformModel& model, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> translation(-0.5, 0.5);
  std::uniform_real_distribution<double> rotation(-0.5236, 0.5236);
  std::vector<Pose> poses;
  poses.reserve(static_cast<std::size_t>(count));
  while (static_cast<int>(poses.size()) < count) {
    Pose pose = model.home_pose();
    for (int k = 0; k < 3; ++k) pose.p_BoMo_B(k) += translation(rng);
    for (int k = 0; k < 3; ++k) pose.rpy_rad(k) += rotation(rng);
    if (CheckWorkspace(model, pose).ok()) poses.push_back(pose);
  }
  return poses;
}

}  // namespace edsp::test_support
