#pragma once
// What the launcher does when a member exits: restart it after a backoff,
// or let it be done, and whether the group must stop. A member down for
// good stops the whole group: a stack with a hole is not safe to run.

#include "group_file.h"

namespace edsp {

struct ExitDecision {
  bool restart = false;
  int backoff_ms = 0;            // restart: after this long
  bool stop_group = false;       // the --until-exit member finished, or one failed for good
  bool failed_for_good = false;  // failed and not restarted: the launcher exits non-zero
};

// 100 ms, doubling per restart already made, at most 5 s.
int RestartBackoffMs(int restarts_made);

// `failed`: no clean exit 0. `until_exit_member`: the member whose clean
// exit ends the run. `group_stopping`: the group is stopping already (no
// restart then).
ExitDecision DecideOnExit(const MemberSpec& spec, int restarts_made, bool failed, bool until_exit_member,
                          bool group_stopping);

}  // namespace edsp
