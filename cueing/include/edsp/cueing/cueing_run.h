#pragma once
// A manoeuvre through a cueing algorithm (cueing_algorithm.h) offline, at the setpoint rate:
// every setpoint through the kinematics' whole-path check (the checks the
// kinematics node applies at run time, and the legs' speed and
// acceleration the drives follow), and what a rider on the commanded
// platform would perceive scored against what the vehicle makes them feel.

#include <string>
#include <vector>

#include "edsp/cueing/cueing_algorithm.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/manoeuvre.h"
#include "edsp/cueing/perception_score.h"
#include "edsp/kinematics/path_check.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct CueingRun {
  VehicleSeries vehicle;
  std::vector<Pose> commanded;    // one per vehicle sample, from the home pose
  VehicleSeries platform;         // what the commanded poses make the head feel
  PathCheck path;                 // the first setpoint the kinematics would refuse, or ok
  double peak_stroke_used = 0.0;  // max |leg − home leg| over the room to the nearer stroke end
  PerceptionScore score;
};

CueingRun RunCueing(const PlatformModel& model, const CueingConfig& config, CueingAlgorithm algorithm,
                    const Manoeuvre& manoeuvre);

// One CSV row per sample: t_s, the vehicle's six channels, the commanded
// pose (x y z roll pitch yaw), the platform's six channels at the head.
std::string CueingRunCsv(const CueingRun& run);

}  // namespace edsp
