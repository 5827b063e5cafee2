#pragma once
// Calibration motions: a motion set designed for identifying the leg-error
// vocabulary (planner/identifiability.h), run by `edsp-planner --motions
// calibration` and `edsp-sim rig --motions calibration`.
//
// Poses are chosen from candidates spread over the workspace, rotations
// included, by a greedy Ds-optimal design: each next pose is the one that
// most increases det of the static parameters' information once the
// tracker's frame is estimated. Each pose is approached from below and from
// above (every leg reverses: backlash), the moves between poses sweep the
// legs' speed (servo lag, inertial compliance), and every block starts and
// ends at the home pose (drift over time). The poses are dealt out to
// `blocks` runs ("cal1", "cal2", …) that each hold the whole mix, so
// edsp-gap can hold any one of them out.

#include <cstdint>
#include <vector>

#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/identifiability.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/planner/trajectory.h"

namespace edsp {

struct CalibrationMotionOptions {
  int poses = 12;
  int blocks = 4;
  int candidates = 400;
  double coverage = 0.8;     // candidates within this share of each axis's paper range
  double approach_m = 0.01;  // along z, below and above each pose
  // Kept clear of the nominal workspace's limits: the real platform's
  // joints sit where the calibration has yet to find them.
  double joint_angle_margin_rad = 3.0 * 3.14159265358979323846 / 180.0;
  double stroke_margin_m = 0.02;
  // No leg carries more of the platform's weight than at the paper's own
  // single-axis extremes (±range on each axis), whatever the payload: the
  // drives were sized for those.
  double min_move_s = 0.5;                                 // the approaches' quintic moves at least this long
  std::vector<double> leg_speed_levels = {0.3, 0.6, 0.9};  // peak leg speed, share of leg_speed_max_m_s
  std::uint64_t seed = 1;
  IdentifiabilityOptions identifiability;  // the noise and PR mode the selection assumes
};

// The selected poses (x y z roll pitch yaw), in order of selection. Throws
// std::invalid_argument if fewer than `poses` candidates are reachable.
std::vector<Vector6> SelectCalibrationPoses(const PlatformModel& model, const PaperMotionOptions& paper,
                                            const CalibrationMotionOptions& options);

// The criterion the selection maximises: log det of the static effects'
// information from the poses (each approached from both sides) once the
// tracker's frame is estimated.
double StaticDesignCriterion(const PlatformModel& model, const std::vector<Vector6>& poses,
                             const IdentifiabilityOptions& options);

// Appends the blocks (segments "cal<b>/move <label>", "cal<b>/dwell <label>")
// starting from the sequence's end (home if empty). Dwells last paper.dwell_s.
void AppendCalibrationMotions(const PlatformModel& model, const PaperMotionOptions& paper,
                              const CalibrationMotionOptions& options, TrajectorySequence* sequence);

// A quintic move whose peak leg speed is `leg_speed_m_s` (never shorter than
// `min_duration_s`).
QuinticMove QuinticAtLegSpeed(const PlatformModel& model, const Vector6& from, const Vector6& to, double leg_speed_m_s,
                              double min_duration_s);

}  // namespace edsp
