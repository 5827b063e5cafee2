#pragma once
// One member's process: its command line, its start (own process group,
// dies with the launcher), its exec in place (systemd units), and its stop
// (SIGINT, then SIGTERM, then SIGKILL).

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "group_file.h"

namespace edsp {

// `command` itself if it holds a '/', else bin_dir/command if that is an
// executable, else `command` (looked up on PATH by exec).
std::string ResolveCommand(const std::string& command, const std::string& bin_dir);

// The member's argv: its program and args, then, for an edsp node, the
// group's config, group file, session and its own name.
std::vector<std::string> MemberArgv(const MemberSpec& spec, const GroupSpec& group, std::int64_t session_id,
                                    const std::string& bin_dir);

// Environment, scheduling (CPU affinity, SCHED_FIFO where allowed), then
// exec. Returns only if exec failed (said on stderr).
void ExecMember(const MemberSpec& spec, std::vector<std::string> argv);

// Forks and execs the member in a process group of its own (Ctrl-C reaches
// the launcher only, which stops the group in order) that receives SIGTERM
// if the launcher dies (no orphans). Returns its pid.
pid_t StartMember(const MemberSpec& spec, std::vector<std::string> argv);

// Stops a started member: SIGINT, SIGTERM after 2 s, SIGKILL after 1 s
// more; reaps it. Returns the signal that stopped it ("SIGINT", ...).
const char* StopMember(pid_t pid);

// A wait status that is no clean exit 0.
bool ExitFailed(int status);
// "exit 3" or "signal 9".
std::string DescribeExit(int status);

}  // namespace edsp
