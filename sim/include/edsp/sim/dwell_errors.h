#pragma once
// Where point A really stood at the end of every dwell of a recorded run,
// against where the target pose puts it: what the paper's Table 1 and
// Figs. 6–9 report, here measured by the tracker in an edsp log.

#include <cstdint>
#include <string>
#include <vector>

#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct DwellError {
  std::string motion;                    // "Lz" (the trajectory name up to '/')
  std::string segment;                   // "Lz/dwell 3"
  PrMode pr_mode = PrMode::kNone;        // of the leg commands during the dwell
  Vector6 target = Vector6::Zero();      // pose, m and rad
  double displacement = 0.0;             // along the motion's axis from home, m or rad
  Vector3 error_m = Vector3::Zero();     // measured − target point A, tracker frame = {B}
  int samples = 0;                       // tracker samples averaged
  std::int64_t averaged_from_utime = 0;  // the window they were averaged over,
  std::int64_t averaged_to_utime = 0;    // by the dwell's setpoint stamps
  double error_norm_m() const { return error_m.norm(); }
};

struct DwellErrors {
  std::vector<DwellError> dwells;  // in the order they were run
  bool damaged = false;            // the log ended in damage; dwells before it are kept
  std::int64_t damage_offset = -1;
};

// Averages the valid tracker samples over the last `averaged_fraction` of
// each dwell (the servo has settled; averaging beats the tracker's noise
// down). Assumes the tracker frame is {B} (the virtual rig's default). Throws
// std::runtime_error naming the log if it cannot be read.
DwellErrors DwellErrorsFromLog(const std::string& log_path, const PlatformModel& model, double averaged_fraction = 0.5);

// Lx Ly Lz Rx Ry Rz → 0…5, the index in [x y z roll pitch yaw]; −1 otherwise.
int MotionAxis(const std::string& motion);

}  // namespace edsp
