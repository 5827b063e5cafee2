#pragma once
// edsp-cueing score: a live run's cueing scored from its log (live_score.h).
//   edsp-cueing score --log RUN.lcmlog --cueing FILE [--json]
// The vehicle as the group heard it on EDSP_VEHICLE (a host on the bus,
// `send --to lcm`, or a UDP host's packets as the cueing took them), the
// commanded poses of the longest stretch the planner followed the cueing
// (EDSP_SETPOINT, trajectory "cueing"), the real ones from EDSP_RIG_TRUTH
// (the virtual rig) or else EDSP_PLATFORM_STATE (the encoders' pose, a
// real rig). Exits 1 naming what is missing when the log cannot be scored.

#include <string>

namespace edsp {

struct ScoreOptions {
  std::string log_path;
  std::string cueing_path;
  bool json = false;
};

int RunScore(const ScoreOptions& options);

}  // namespace edsp
