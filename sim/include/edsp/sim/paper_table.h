#pragma once
// The paper's four single-axis test motions (Huang et al. 2021, Sect. 4) and
// the point-A accuracy each PR compensation mode achieves on them: commands
// built with the mode, the platform moved by the TRUE signed PR (forward
// kinematics from the commanded lengths), A compared with where it should be.

#include <array>
#include <string>
#include <vector>

#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct TestMotion {
  std::string name;  // "Lz", "Lx", "Rz", "Ry"
  int axis;          // index into q = [x y z roll pitch yaw]
  double amplitude;  // m or rad: the motion spans −amplitude … +amplitude
};

// Lz, Lx over ±0.5 m and Rz, Ry over ±30°, in the paper's order.
std::vector<TestMotion> PaperTestMotions();

// `count` evenly spaced poses from −amplitude to +amplitude about home.
std::vector<Pose> MotionPoses(const TestMotion& motion, const Pose& home, int count);

// The modes the table compares, in column order.
inline constexpr std::array<PrMode, 4> kTableModes = {PrMode::kNone, PrMode::kUnsigned, PrMode::kSigned, PrMode::kAsin};

// Distance between where A lands and where it should be, for a pose commanded
// with `mode`. Throws std::runtime_error (naming pose and status) if forward
// kinematics fails.
double PointAError(const PlatformModel& model, const Pose& target, PrMode mode);

struct MotionRow {
  TestMotion motion;
  std::array<double, kTableModes.size()> max_error_m;  // per kTableModes entry
};

// Every motion's poses must lie in the workspace: a pose outside throws
// std::runtime_error naming the motion, the pose and the limit.
std::vector<MotionRow> PaperTable(const PlatformModel& model, int poses_per_motion = 41);

}  // namespace edsp
