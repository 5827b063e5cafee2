#pragma once
// `edsp-sim rig`: the virtual rig, with the effects of the config's
// [rig.effects], driven through test motions by the same planner, kinematics
// node and actuator bridge as the live stack, in one process and faster than
// real time. Writes what the live group's logger would record (an LCM log of
// the edsp channels) and its measurement CSV (interfaces.md §3).

#include <cstdint>
#include <string>
#include <vector>

#include "edsp/planner/paper_motions.h"
#include "edsp/rig/virtual_rig.h"

namespace edsp {

struct OfflineRunOptions {
  std::vector<std::string> motions = {"Lz", "Lx", "Rz", "Ry"};
  PaperMotionOptions paper;
  PrMode pr_mode = PrMode::kSigned;
  TrackerParameters tracker;  // frame, noise, rate, seed
  std::string out_dir = ".";
  // An edsp-gap model the kinematics applies (empty: the config's
  // [calibration] model, if any); ambiguous effects only if asked.
  std::string calibration_path;
  bool apply_ambiguous = false;
};

struct OfflineRunResult {
  std::string log_path;     // <out_dir>/run.lcmlog
  std::string csv_path;     // <out_dir>/measurement.csv
  std::int64_t cycles = 0;  // 1 ms each
  std::int64_t tracker_samples = 0;
  std::int64_t faults = 0;   // refused setpoints or commands (none expected)
  double duration_s = 0.0;   // simulated
  double max_error_m = 0.0;  // |tracker A − target A| over every tracker sample
  double rms_error_m = 0.0;  //   (tracker frame taken as {B})
  std::string calibration;   // what the kinematics applied (CalibrationModel::Describe), or empty
};

// Throws ConfigError for a bad config, std::invalid_argument for a motion
// outside the workspace, std::runtime_error naming the file it cannot write.
OfflineRunResult RunOffline(const std::string& config_path, const OfflineRunOptions& options);

// The same with the rig's effects given (not read from the config).
OfflineRunResult RunOffline(const std::string& config_path, const RigEffects& effects,
                            const OfflineRunOptions& options);

// The point-A error each enabled effect of the config produces alone, on the
// options' motions (tracker noise as given): what `edsp-sim rig --per-effect`
// prints. Runs go to <out_dir>/<effect>/.
struct EffectError {
  std::string effect;
  double max_error_m = 0.0, rms_error_m = 0.0;
};
std::vector<EffectError> PerEffectErrors(const std::string& config_path, const OfflineRunOptions& options);

}  // namespace edsp
