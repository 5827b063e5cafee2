#pragma once
// The paper's single-axis test motions (Lz, Lx ±0.5 m; Rz, Ry ±30°) and the
// other axes (Ly, Rx), as trajectories a rig can run: from home to each of
// `stops` evenly spaced poses across the range, dwelling at each, then home.
// Segments are named "<motion>/move <k>" and "<motion>/dwell <k>".

#include <memory>
#include <string>
#include <vector>

#include "edsp/planner/trajectory.h"

namespace edsp {

struct PaperMotionOptions {
  int stops = 5;         // poses across −range … +range
  double dwell_s = 1.0;  // at each stop
  double max_speed_m_s = 0.1;
  double max_speed_rad_s = 0.2;
  double linear_range_m = 0.5;
  double angular_range_rad = 30.0 * 3.14159265358979323846 / 180.0;
};

// Known names: Lx Ly Lz Rx Ry Rz, and the mixed motions M1 … M999: every
// axis at once, `stops` poses drawn deterministically (from the number)
// within 35% of each axis's range at half of each axis's speed, then home. Throws std::invalid_argument
// for others.
void AppendPaperMotion(const std::string& name, const Vector6& home, const PaperMotionOptions& options,
                       TrajectorySequence* sequence);

// Lz, Lx, Rz, Ry one after another (the paper's order).
std::vector<std::string> PaperMotionNames();

// "Lz,Lx,Rz" → {"Lz", "Lx", "Rz"}; empty names are dropped.
std::vector<std::string> MotionNames(const std::string& list);

// The named paper motions one after another, from `home`. Throws
// std::invalid_argument naming an unknown one.
std::unique_ptr<TrajectorySequence> PaperMotionSequence(const std::vector<std::string>& names, const Vector6& home,
                                                        const PaperMotionOptions& options);

}  // namespace edsp
