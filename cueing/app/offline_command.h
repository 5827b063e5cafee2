#pragma once
// edsp-cueing offline and omct: manoeuvres through a cueing algorithm,
// checked and scored without a rig (docs/cueing.md).
//   edsp-cueing offline --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                       [--csv-dir DIR] [--plot DIR] [--algorithm classical_washout|mpc] [--json]
//   edsp-cueing omct --config FILE --cueing FILE [--json]

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/omct.h"
#include "edsp/kinematics/config.h"
#include "edsp/rig/rig_effects.h"

namespace edsp {

struct OfflineOptions {
  std::string config_path;
  std::string cueing_path;
  std::vector<std::string> manoeuvre_paths;
  std::string rig_effects_path;
  std::string csv_dir;
  std::string plot_dir;
  std::string algorithm;  // empty: the cueing config's [cueing] algorithm
  bool json = false;
};

int RunOffline(const OfflineOptions& options);
// The OMCT's direct responses of classical washout, as a table or JSON.
int RunOmctTable(const std::string& config_path, const std::string& cueing_path, bool json);

// What a rider on the rig feels: the commanded poses played through the
// stack and a rig with its effects.
PerceptionScore ScoreOnTheRig(const PlatformConfig& nominal, const RigEffects& effects, const CueingConfig& config,
                              const CueingRun& run);
// The OMCT's points by channel: frequency, gain, phase.
nlohmann::json OmctJson(const std::vector<OmctPoint>& points);

}  // namespace edsp
