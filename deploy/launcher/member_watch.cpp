#include "member_watch.h"

#include <fstream>
#include <sstream>

namespace edsp {

ProcessState ReadProcessState(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return ProcessState::kGone;
  // "pid (comm) S ...": comm may hold spaces and parentheses; the state
  // follows the last ')'.
  const std::size_t close = line.rfind(')');
  if (close == std::string::npos || close + 2 >= line.size()) return ProcessState::kGone;
  switch (line[close + 2]) {
    case 'T': return ProcessState::kStopped;
    case 't': return ProcessState::kTraced;
    case 'Z':
    case 'X': return ProcessState::kGone;
    default: return ProcessState::kRunning;
  }
}

FreezeWatch::Change FreezeWatch::Observe(ProcessState state, std::int64_t now_us) {
  if (state == ProcessState::kTraced) {
    if (traced_since_us_ < 0) traced_since_us_ = now_us;
    if (now_us - traced_since_us_ < kTracedFreezeUs) return Change::kNone;
    state = ProcessState::kStopped;
  } else {
    traced_since_us_ = -1;
  }
  if (state == ProcessState::kStopped && !frozen_) {
    frozen_ = true;
    since_us_ = now_us;
    return Change::kFroze;
  }
  if (state == ProcessState::kRunning && frozen_) {
    frozen_ = false;
    return Change::kResumed;
  }
  return Change::kNone;
}

}  // namespace edsp
