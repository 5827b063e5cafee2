// edsp-launch: starts a process group, watches it, restarts crashed members
// with backoff, and stops it in reverse order on Ctrl-C (SIGINT → SIGTERM →
// SIGKILL). Exits non-zero if a member failed for good.
//   edsp-launch GROUP_FILE [--host NAME] [--session-id N] [--duration-s S]
//                          [--until-exit MEMBER] [--bin-dir DIR]
#include <signal.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "edsp/node/runtime.h"
#include "group_file.h"

namespace edsp {
namespace {

using Clock = std::chrono::steady_clock;

struct Member {
  MemberSpec spec;
  pid_t pid = -1;
  int restarts = 0;
  bool done = false;     // exited and will not be restarted
  bool failed = false;
  Clock::time_point restart_at{};
};

std::string Resolve(const std::string& command, const std::string& bin_dir) {
  if (command.find('/') != std::string::npos) return command;
  const std::string candidate = bin_dir + "/" + command;
  return ::access(candidate.c_str(), X_OK) == 0 ? candidate : command;  // else PATH
}

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

pid_t Start(const Member& m, const GroupSpec& group, std::int64_t session_id,
            const std::string& bin_dir) {
  std::vector<std::string> argv{Resolve(m.spec.command, bin_dir)};
  argv.insert(argv.end(), m.spec.args.begin(), m.spec.args.end());
  if (m.spec.node_options) {
    argv.insert(argv.end(), {"--config", group.config, "--group", group.path, "--session-id",
                             std::to_string(session_id)});
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);                    // Ctrl-C reaches the launcher only: it stops in order
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // and a dead launcher leaves no orphans
    for (const auto& [name, value] : m.spec.env) ::setenv(name.c_str(), value.c_str(), 1);
    ApplyScheduling(m.spec);
    std::vector<char*> raw;
    for (std::string& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    ::execvp(raw[0], raw.data());
    std::fprintf(stderr, "edsp-launch: %s: cannot run %s\n", m.spec.name.c_str(), raw[0]);
    ::_exit(127);
  }
  std::fprintf(stderr, "edsp-launch: %-16s started  pid %d\n", m.spec.name.c_str(), pid);
  return pid;
}

bool WaitExit(pid_t pid, std::chrono::milliseconds limit, int* status) {
  const auto until = Clock::now() + limit;
  while (Clock::now() < until) {
    if (::waitpid(pid, status, WNOHANG) == pid) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

void StopAll(std::vector<Member>& members) {
  for (auto it = members.rbegin(); it != members.rend(); ++it) {
    if (it->pid <= 0) continue;
    int status = 0;
    const char* how = "SIGINT";
    ::kill(it->pid, SIGINT);
    if (!WaitExit(it->pid, std::chrono::milliseconds(2000), &status)) {
      how = "SIGTERM";
      ::kill(it->pid, SIGTERM);
      if (!WaitExit(it->pid, std::chrono::milliseconds(1000), &status)) {
        how = "SIGKILL";
        ::kill(it->pid, SIGKILL);
        ::waitpid(it->pid, &status, 0);
      }
    }
    std::fprintf(stderr, "edsp-launch: %-16s stopped  (%s)\n", it->spec.name.c_str(), how);
    it->pid = -1;
  }
}

bool Failed(int status) { return !WIFEXITED(status) || WEXITSTATUS(status) != 0; }

std::string Describe(int status) {
  return WIFEXITED(status) ? fmt::format("exit {}", WEXITSTATUS(status))
                           : fmt::format("signal {}", WTERMSIG(status));
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-launch: start, watch and stop an edsp process group"};
  std::string group_path, host, until_exit, bin_dir;
  std::int64_t session_id = 0;
  double duration_s = 0.0;
  app.add_option("group", group_path, "group file (TOML)")->required();
  app.add_option("--host", host, "start only the members on this host");
  app.add_option("--session-id", session_id, "session id (default: the file's, or a fresh one)");
  app.add_option("--duration-s", duration_s, "stop the group after this long (0: run until Ctrl-C)");
  app.add_option("--until-exit", until_exit, "stop the group when this member exits successfully");
  app.add_option("--bin-dir", bin_dir, "where the edsp programs are (default: beside edsp-launch)");
  CLI11_PARSE(app, argc, argv);

  const GroupSpec group = LoadGroupFile(group_path);
  if (bin_dir.empty()) {
    char self[4096] = {0};
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    bin_dir = n > 0 ? std::string(self, static_cast<std::size_t>(n)) : ".";
    bin_dir = bin_dir.substr(0, bin_dir.rfind('/'));
  }
  if (session_id == 0) session_id = group.session_id;
  if (session_id == 0) session_id = (UtimeNow() / 1000) & 0x7fffffff;  // fresh per launch
  std::vector<Member> members;
  for (const MemberSpec& spec : group.members) {
    if (host.empty() || spec.host == host) members.push_back(Member{spec});
  }
  if (members.empty()) throw std::runtime_error(group_path + ": no member on host " + host);
  if (!until_exit.empty() &&
      std::none_of(members.begin(), members.end(), [&](const Member& m) { return m.spec.name == until_exit; })) {
    throw std::runtime_error("--until-exit " + until_exit + ": no such member");
  }
  InstallStopSignals();
  std::fprintf(stderr, "edsp-launch: group %s, session %lld, %zu members\n", group.name.c_str(),
               static_cast<long long>(session_id), members.size());
  for (Member& m : members) {
    if (StopRequested()) break;
    m.pid = Start(m, group, session_id, bin_dir);
    std::this_thread::sleep_for(std::chrono::milliseconds(m.spec.start_delay_ms));
  }
  const auto started = Clock::now();
  bool failed = false, stopping = false;
  while (!stopping) {
    int status = 0;
    pid_t pid;
    while ((pid = ::waitpid(-1, &status, WNOHANG)) > 0) {
      for (Member& m : members) {
        if (m.pid != pid) continue;
        m.pid = -1;
        std::fprintf(stderr, "edsp-launch: %-16s exited   (%s)\n", m.spec.name.c_str(), Describe(status).c_str());
        if (m.spec.name == until_exit && !Failed(status)) stopping = true;
        const bool restart = !stopping && m.restarts < m.spec.max_restarts &&
                             (m.spec.restart == RestartPolicy::kAlways ||
                              (m.spec.restart == RestartPolicy::kOnFailure && Failed(status)));
        if (restart) {
          const int backoff_ms = std::min(5000, 100 << std::min(m.restarts, 6));
          m.restart_at = Clock::now() + std::chrono::milliseconds(backoff_ms);
          ++m.restarts;
          std::fprintf(stderr, "edsp-launch: %-16s restart %d in %d ms\n", m.spec.name.c_str(), m.restarts, backoff_ms);
        } else {
          m.done = true;
          if (Failed(status)) {
            m.failed = failed = true;
            stopping = true;  // a member down for good: the group is not safe to run
          }
        }
      }
    }
    for (Member& m : members) {
      if (!stopping && m.pid < 0 && !m.done && Clock::now() >= m.restart_at) {
        m.pid = Start(m, group, session_id, bin_dir);
      }
    }
    if (StopRequested()) stopping = true;
    if (duration_s > 0.0 && Clock::now() - started >= std::chrono::duration<double>(duration_s)) stopping = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  StopAll(members);
  for (const Member& m : members) {
    if (m.failed) std::fprintf(stderr, "edsp-launch: %s failed\n", m.spec.name.c_str());
  }
  return failed ? 1 : 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-launch", edsp::Run, argc, argv, 2); }
