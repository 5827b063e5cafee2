#include "restart_policy.h"

#include <algorithm>

namespace edsp {

int RestartBackoffMs(int restarts_made) { return std::min(5000, 100 << std::clamp(restarts_made, 0, 6)); }

ExitDecision DecideOnExit(const MemberSpec& spec, int restarts_made, bool failed, bool until_exit_member,
                          bool group_stopping) {
  ExitDecision d;
  d.stop_group = group_stopping || (until_exit_member && !failed);
  const bool policy_restarts =
      spec.restart == RestartPolicy::kAlways || (spec.restart == RestartPolicy::kOnFailure && failed);
  d.restart = !d.stop_group && restarts_made < spec.max_restarts && policy_restarts;
  if (d.restart) {
    d.backoff_ms = RestartBackoffMs(restarts_made);
  } else if (failed) {
    d.failed_for_good = true;
    d.stop_group = true;
  }
  return d;
}

}  // namespace edsp
