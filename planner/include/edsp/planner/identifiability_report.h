#pragma once
// edsp-planner --identifiability: how well a motion set lets edsp-gap
// identify each effect (identifiability.h), beside the paper's four motions,
// as a table or JSON on stdout.

#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/identifiability.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/planner/trajectory.h"

namespace edsp {

// Throws std::invalid_argument when a pose of `motions` is outside the
// workspace (a motion set the planner would refuse is not one to judge).
void ReportIdentifiability(const PlatformModel& model, const TrajectorySequence& motions,
                           const PaperMotionOptions& paper, const IdentifiabilityOptions& options, bool json);

}  // namespace edsp
