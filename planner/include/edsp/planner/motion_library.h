#pragma once
// Every motion edsp plans by name: the paper's single-axis motions and the
// mixed ones (paper_motions.h), and "calibration", the motion set designed
// for identification (calibration_motions.h). Part of the motion design
// (edsp_motion_design), not of the planner's core: the planner's motion
// service is given it as its ProgramLibrary by edsp-planner.

#include <string>
#include <vector>

#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/calibration_motions.h"
#include "edsp/planner/paper_motions.h"

namespace edsp {

// Throws std::invalid_argument naming an unknown motion and the known ones.
void AppendMotion(const PlatformModel& model, const std::string& name, const PaperMotionOptions& paper,
                  TrajectorySequence* sequence, const CalibrationMotionOptions& calibration = {});

// The named motions one after another, from home.
std::unique_ptr<TrajectorySequence> MotionSequence(const PlatformModel& model, const std::vector<std::string>& names,
                                                   const PaperMotionOptions& paper,
                                                   const CalibrationMotionOptions& calibration = {});

// What edsp-planner plays: the trajectory CSV `csv_path` (approached from
// home by a quintic move within the speed limits when it starts
// elsewhere), or without one the motions named in `motions` (a list as
// above). Throws std::runtime_error / std::invalid_argument naming a bad
// file or an unknown motion.
std::unique_ptr<TrajectorySequence> PlannedTrajectory(const PlatformModel& model, const std::string& motions,
                                                      const std::string& csv_path, const PaperMotionOptions& paper);

}  // namespace edsp
