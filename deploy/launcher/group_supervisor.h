#pragma once
// Runs one host's members of a group (or all of them): starts them in the
// file's order with their start delays, reaps exits and restarts members by
// their policy with backoff (restart_policy.h), watches for frozen members
// (member_watch.h), reports all of it (group_report.h), and stops the
// members in reverse order. edsp-launch's main only parses options and runs
// one.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "group_file.h"
#include "group_report.h"
#include "member_watch.h"

namespace edsp {

struct SupervisorOptions {
  std::string host;  // empty: every member
  std::int64_t session_id = 0;
  std::string bin_dir;     // where the programs are
  std::string until_exit;  // a member whose clean exit ends the run (empty: none)
};

class GroupSupervisor {
 public:
  // Throws std::runtime_error naming the file when no member runs on the
  // host or --until-exit names no member there (checked first); then
  // TransportError if LCM cannot be opened for the report.
  GroupSupervisor(const GroupSpec& group, SupervisorOptions options);
  ~GroupSupervisor();  // stops whatever still runs, in reverse order
  GroupSupervisor(const GroupSupervisor&) = delete;
  GroupSupervisor& operator=(const GroupSupervisor&) = delete;

  // Starts the members in order, pausing each one's start delay; stops
  // early once `stop()` says so.
  void StartAll(const std::function<bool()>& stop);
  // One pass: reaps exits and acts on them, starts members whose restart is
  // due, watches freezes, reports. False once the group must stop.
  bool Step();
  // In reverse order (member_process.h StopMember).
  void StopAll();

  // StartAll, Step every 10 ms until the group must stop, `stop()` or
  // `duration` (zero: none) passes, then StopAll. Returns the exit code:
  // 1 if a member failed for good, else 0.
  int Run(std::chrono::duration<double> duration, const std::function<bool()>& stop);

  bool failed() const;
  std::size_t member_count() const { return members_.size(); }

 private:
  using Clock = std::chrono::steady_clock;
  struct Member {
    MemberSpec spec;
    pid_t pid = -1;
    int restarts = 0;
    bool done = false;  // exited and will not be restarted
    bool failed = false;
    Clock::time_point restart_at{};
    FreezeWatch freeze;
  };

  static std::vector<Member> SelectMembers(const GroupSpec& group, const SupervisorOptions& options);
  void Start(Member& m);
  void OnExit(Member& m, int status);
  void WatchFreezes();
  bool Healthy() const;

  GroupSpec group_;
  SupervisorOptions options_;
  std::vector<Member> members_;
  GroupReport report_;
  bool stopping_ = false;
};

}  // namespace edsp
