#include "member_process.h"

#include <signal.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include <fmt/format.h>

namespace edsp {

namespace {

// In the child, before exec. Without the privilege (not root, no
// CAP_SYS_NICE, or RLIMIT_RTPRIO 0) the member still runs, as SCHED_OTHER.
void ApplyScheduling(const MemberSpec& spec) {
  if (!spec.cpus.empty()) {
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int cpu : spec.cpus) CPU_SET(cpu, &set);
    if (::sched_setaffinity(0, sizeof(set), &set) != 0) {
      std::fprintf(stderr, "edsp-launch: %s: warning: cpus affinity refused (%s); running on any CPU\n",
                   spec.name.c_str(), std::strerror(errno));
    }
  }
  if (spec.realtime_priority <= 0) return;
  sched_param param{};
  param.sched_priority = spec.realtime_priority;
  if (::sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
    std::fprintf(stderr, "edsp-launch: %s: warning: SCHED_FIFO %d refused (%s); running unprioritised\n",
                 spec.name.c_str(), spec.realtime_priority, std::strerror(errno));
  }
}

bool WaitExit(pid_t pid, std::chrono::milliseconds limit, int* status) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (::waitpid(pid, status, WNOHANG) == pid) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

}  // namespace

std::string ResolveCommand(const std::string& command, const std::string& bin_dir) {
  if (command.find('/') != std::string::npos) return command;
  const std::string candidate = bin_dir + "/" + command;
  return ::access(candidate.c_str(), X_OK) == 0 ? candidate : command;  // else PATH
}

std::vector<std::string> MemberArgv(const MemberSpec& spec, const GroupSpec& group, std::int64_t session_id,
                                    const std::string& bin_dir) {
  std::vector<std::string> argv{ResolveCommand(spec.command, bin_dir)};
  argv.insert(argv.end(), spec.args.begin(), spec.args.end());
  if (spec.node_options) {
    argv.insert(argv.end(), {"--config", group.config, "--group", group.path, "--session-id",
                             std::to_string(session_id), "--member", spec.name});
  }
  return argv;
}

void ExecMember(const MemberSpec& spec, std::vector<std::string> argv) {
  for (const auto& [name, value] : spec.env) ::setenv(name.c_str(), value.c_str(), 1);
  ApplyScheduling(spec);
  std::vector<char*> raw;
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  ::execvp(raw[0], raw.data());
  std::fprintf(stderr, "edsp-launch: %s: cannot run %s (%s)\n", spec.name.c_str(), raw[0], std::strerror(errno));
}

pid_t StartMember(const MemberSpec& spec, std::vector<std::string> argv) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child never unwinds into the launcher's stack (its destructors
    // would stop the siblings): whatever happens, it execs or exits here.
    try {
      ::setpgid(0, 0);
      ::prctl(PR_SET_PDEATHSIG, SIGTERM);
      ExecMember(spec, std::move(argv));
    } catch (...) {
    }
    ::_exit(127);
  }
  return pid;
}

const char* StopMember(pid_t pid) {
  int status = 0;
  ::kill(pid, SIGINT);
  if (WaitExit(pid, std::chrono::milliseconds(2000), &status)) return "SIGINT";
  ::kill(pid, SIGTERM);
  if (WaitExit(pid, std::chrono::milliseconds(1000), &status)) return "SIGTERM";
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return "SIGKILL";
}

bool ExitFailed(int status) { return !WIFEXITED(status) || WEXITSTATUS(status) != 0; }

std::string DescribeExit(int status) {
  return WIFEXITED(status) ? fmt::format("exit {}", WEXITSTATUS(status)) : fmt::format("signal {}", WTERMSIG(status));
}

}  // namespace edsp
