// edsp-launch: starts a process group, watches it, restarts crashed members
// with backoff, and stops it in reverse order on Ctrl-C (SIGINT → SIGTERM →
// SIGKILL). Exits non-zero if a member failed for good. A member that
// freezes (stopped by a signal), exits or restarts is reported on EDSP_FAULT
// (node "launcher"), and the launcher's EDSP_STATUS is STATE_FAULT meanwhile.
//   edsp-launch GROUP_FILE [--host NAME] [--session-id N] [--duration-s S]
//                          [--until-exit MEMBER] [--bin-dir DIR]
//   edsp-launch GROUP_FILE --member NAME      run one member in place (systemd units)
//   edsp-launch GROUP_FILE --host NAME --write-units DIR [--root DIR]
//                                             write that host's systemd units
#include <signal.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "edsp/node/fault.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"
#include "edsp/transport/transport_config.h"
#include "group_file.h"
#include "member_watch.h"
#include "multicast_route.h"
#include "systemd_units.h"

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
  FreezeWatch freeze;
};

// The launcher's voice on the group's bus: EDSP_FAULT and EDSP_STATUS over
// LCM (never shm: the launcher is no member of the routes), as node
// "launcher", or "launcher@<host>" for one host's members (one per host).
class GroupReport {
 public:
  GroupReport(const GroupSpec& group, const std::string& host)
      : node_(host.empty() ? "launcher" : "launcher@" + host),
        bus_(LcmOnly(group.path)),
        faults_(bus_.Advertise<fault_t>("EDSP_FAULT")),
        status_out_(bus_.Advertise<node_status_t>("EDSP_STATUS")),
        status_(node_) {
    status_.SetState(node_status_t::STATE_RUNNING);
  }
  void Fault(const std::string& member, std::int8_t severity, const std::string& reason) {
    faults_.Publish(MakeFault(node_, "", FaultCode::kProcess, severity,
                              fmt::format("member {}: {}", member, reason), UtimeNow()));
    status_.CountOut();
  }
  // Once a second, and at once when health changes; `healthy`: no member
  // frozen or waiting to restart.
  void Tick(bool healthy) {
    status_.SetState(healthy ? node_status_t::STATE_RUNNING : node_status_t::STATE_FAULT);
    const std::int64_t now = UtimeNow();
    if (status_.Due(now)) status_out_.Publish(status_.Report(now, 0));
  }

 private:
  static TransportConfig LcmOnly(const std::string& path) {
    TransportConfig config = LoadTransportConfig(path);
    config.channels.clear();
    return config;
  }
  std::string node_;
  Bus bus_;
  Bus::Publisher<fault_t> faults_;
  Bus::Publisher<node_status_t> status_out_;
  NodeStatus status_;
};

// Frozen and resumed members, from the process table.
void WatchFreezes(std::vector<Member>& members, GroupReport& report) {
  const std::int64_t now = UtimeNow();
  for (Member& m : members) {
    if (m.pid <= 0) continue;
    const ProcessState state = ReadProcessState(m.pid);
    const double frozen_ms = static_cast<double>(m.freeze.frozen_for_us(now)) * 1e-3;
    switch (m.freeze.Observe(state, now)) {
      case FreezeWatch::Change::kFroze:
        std::fprintf(stderr, "edsp-launch: %-16s frozen   (stopped)\n", m.spec.name.c_str());
        report.Fault(m.spec.name, fault_t::SEVERITY_ERROR,
                     fmt::format("pid {} is stopped (SIGSTOP, or a tracer for over a second): frozen, not running", m.pid));
        break;
      case FreezeWatch::Change::kResumed:
        std::fprintf(stderr, "edsp-launch: %-16s resumed  after %.0f ms\n", m.spec.name.c_str(), frozen_ms);
        report.Fault(m.spec.name, fault_t::SEVERITY_INFO,
                     fmt::format("pid {} runs again after {:.0f} ms frozen", m.pid, frozen_ms));
        break;
      case FreezeWatch::Change::kNone: break;
    }
  }
}

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

std::vector<std::string> MemberArgv(const MemberSpec& spec, const GroupSpec& group,
                                    std::int64_t session_id, const std::string& bin_dir) {
  std::vector<std::string> argv{Resolve(spec.command, bin_dir)};
  argv.insert(argv.end(), spec.args.begin(), spec.args.end());
  if (spec.node_options) {
    argv.insert(argv.end(), {"--config", group.config, "--group", group.path, "--session-id",
                             std::to_string(session_id), "--member", spec.name});
  }
  return argv;
}

// In the child (or in place of the launcher, --member): environment,
// scheduling, then the program. Returns only if exec failed.
void ExecMember(const MemberSpec& spec, std::vector<std::string> argv) {
  for (const auto& [name, value] : spec.env) ::setenv(name.c_str(), value.c_str(), 1);
  ApplyScheduling(spec);
  std::vector<char*> raw;
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  ::execvp(raw[0], raw.data());
  std::fprintf(stderr, "edsp-launch: %s: cannot run %s (%s)\n", spec.name.c_str(), raw[0], std::strerror(errno));
}

pid_t Start(const Member& m, const GroupSpec& group, std::int64_t session_id,
            const std::string& bin_dir) {
  std::vector<std::string> argv = MemberArgv(m.spec, group, session_id, bin_dir);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);                    // Ctrl-C reaches the launcher only: it stops in order
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // and a dead launcher leaves no orphans
    ExecMember(m.spec, std::move(argv));
    ::_exit(127);
  }
  std::fprintf(stderr, "edsp-launch: %-16s started  pid %d\n", m.spec.name.c_str(), pid);
  return pid;
}

// A host whose [hosts.NAME] names an interface: the group's multicast must
// leave by it, or the members would talk on the wrong network (or none).
void CheckMulticastInterface(const GroupSpec& group, const std::string& host) {
  const auto it = group.hosts.find(host);
  if (it == group.hosts.end() || it->second.interface.empty()) return;
  const std::string url = LoadTransportConfig(group.path).lcm_url;
  const std::string address = MulticastAddress(url);
  if (address.empty()) return;
  std::string error;
  const std::string interface = MulticastRouteInterface(address, &error);
  if (interface != it->second.interface) {
    throw std::runtime_error(fmt::format(
        "{}: [hosts.{}] interface = \"{}\", but the route to the LCM group {} {}; add one with "
        "`ip route add 224.0.0.0/4 dev {}` (docs/multihost.md)",
        group.path, host, it->second.interface, address,
        interface.empty() ? error : "leaves by " + interface, it->second.interface));
  }
}

void WriteUnits(const GroupSpec& group, const std::string& host, const std::string& dir,
                const std::string& root, const std::string& bin_dir) {
  if (host.empty()) throw std::runtime_error("--write-units needs --host: units are written per machine");
  namespace fs = std::filesystem;
  const fs::path template_path = fs::path(root) / "deploy/systemd/edsp@.service";
  if (!fs::exists(template_path)) throw std::runtime_error(template_path.string() + ": no unit template there (--root)");
  std::vector<UnitFile> units = MemberUnits(group, host, root, bin_dir);
  units.push_back({"edsp@.service", ReadTextFile(template_path.string())});
  for (const UnitFile& unit : units) {
    const fs::path path = fs::path(dir) / unit.path;
    fs::create_directories(path.parent_path());
    std::ofstream out(path);
    out << unit.text;
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
    std::printf("%s\n", path.c_str());
  }
}

std::string SelfDirectory() {
  char self[4096] = {0};
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  const std::string path = n > 0 ? std::string(self, static_cast<std::size_t>(n)) : "./x";
  return path.substr(0, path.rfind('/'));
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
  std::string group_path, host, until_exit, bin_dir, only_member, unit_dir, root;
  std::int64_t session_id = 0;
  double duration_s = 0.0;
  app.add_option("group", group_path, "group file (TOML)")->required();
  app.add_option("--host", host, "start only the members on this host");
  app.add_option("--session-id", session_id, "session id (default: the file's, or a fresh one)");
  app.add_option("--duration-s", duration_s, "stop the group after this long (0: run until Ctrl-C)");
  app.add_option("--until-exit", until_exit, "stop the group when this member exits successfully");
  app.add_option("--bin-dir", bin_dir, "where the edsp programs are (default: beside edsp-launch)");
  app.add_option("--member", only_member, "run this one member in place of the launcher (systemd units)");
  app.add_option("--write-units", unit_dir, "write --host's systemd units into this directory, then exit");
  app.add_option("--root", root, "--write-units: the edsp checkout on that host (default: this one)");
  CLI11_PARSE(app, argc, argv);

  const GroupSpec group = LoadGroupFile(group_path);
  if (bin_dir.empty()) bin_dir = SelfDirectory();
  if (!unit_dir.empty()) {
    if (root.empty()) root = std::filesystem::absolute(bin_dir + "/../..").lexically_normal().string();
    if (root.size() > 1 && root.back() == '/') root.pop_back();
    WriteUnits(group, host, unit_dir, root, std::filesystem::absolute(bin_dir).lexically_normal().string());
    return 0;
  }
  if (session_id == 0) session_id = group.session_id;
  if (session_id == 0 && !only_member.empty()) {
    // Each member runs (and restarts) on its own: a session drawn per exec
    // would differ between them, and the bridge would refuse every command.
    throw std::runtime_error(group_path + ": --member needs a fixed session: set [group] session_id (or pass --session-id)");
  }
  if (session_id == 0) session_id = (UtimeNow() / 1000) & 0x7fffffff;  // fresh per launch
  if (!only_member.empty()) {
    const auto spec = std::find_if(group.members.begin(), group.members.end(),
                                   [&](const MemberSpec& m) { return m.name == only_member; });
    if (spec == group.members.end()) throw std::runtime_error("--member " + only_member + ": no such member in " + group_path);
    CheckMulticastInterface(group, spec->host);
    ExecMember(*spec, MemberArgv(*spec, group, session_id, bin_dir));
    return 127;
  }
  if (!host.empty()) CheckMulticastInterface(group, host);
  std::vector<Member> members;
  for (const MemberSpec& spec : group.members) {
    if (host.empty() || spec.host == host) members.push_back(Member{spec, -1, 0, false, false, {}, {}});
  }
  if (members.empty()) throw std::runtime_error(group_path + ": no member on host " + host);
  if (!until_exit.empty() &&
      std::none_of(members.begin(), members.end(), [&](const Member& m) { return m.spec.name == until_exit; })) {
    throw std::runtime_error("--until-exit " + until_exit + ": no such member");
  }
  InstallStopSignals();
  GroupReport report(group, host);
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
        m.freeze.Forget();
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
          report.Fault(m.spec.name, fault_t::SEVERITY_ERROR,
                       fmt::format("exited ({}); restart {} in {} ms", Describe(status), m.restarts, backoff_ms));
        } else {
          m.done = true;
          if (Failed(status) && !stopping) {
            report.Fault(m.spec.name, fault_t::SEVERITY_ERROR,
                         fmt::format("exited ({}) for good; stopping the group", Describe(status)));
          }
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
        if (m.restarts > 0) {
          report.Fault(m.spec.name, fault_t::SEVERITY_INFO, fmt::format("restarted as pid {}", m.pid));
        }
      }
    }
    WatchFreezes(members, report);
    report.Tick(std::none_of(members.begin(), members.end(), [](const Member& m) {
      return m.freeze.frozen() || (m.pid < 0 && !m.done);
    }));
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
