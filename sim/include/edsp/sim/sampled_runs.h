#pragma once
// The motions edsp plans by name, sampled run by run: what another rig's
// controller plays when it runs edsp's own motions (the blind rig, which
// has no planner of edsp's: diagnosis/blind_closed_loop.h).

#include <string>
#include <vector>

#include "edsp/kinematics/platform_model.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/planner/trajectory.h"

namespace edsp {

// One run: the segments whose names share the prefix before '/' ("Lz",
// "cal1", …), as the measurement export names runs.
struct SampledRun {
  std::string name;
  std::vector<PoseSample> samples;  // from the run's first instant to its last, at the rate asked
};

// `names` planned one after another from home (motion_library.h), cut into
// runs and sampled at `rate_hz`. Throws what MotionSequence throws.
std::vector<SampledRun> SampleRuns(const PlatformModel& model, const std::vector<std::string>& names,
                                   const PaperMotionOptions& paper, double rate_hz);

}  // namespace edsp
