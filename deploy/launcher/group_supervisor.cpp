#include "group_supervisor.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "edsp/node/runtime.h"
#include "member_process.h"
#include "restart_policy.h"

namespace edsp {

// The host's members, checked before anything opens: a wrong --host or
// --until-exit is said as such, whatever the network.
std::vector<GroupSupervisor::Member> GroupSupervisor::SelectMembers(const GroupSpec& group,
                                                                    const SupervisorOptions& options) {
  std::vector<Member> members;
  for (const MemberSpec& spec : group.members) {
    if (!options.host.empty() && spec.host != options.host) continue;
    Member m;
    m.spec = spec;
    members.push_back(std::move(m));
  }
  if (members.empty()) throw std::runtime_error(group.path + ": no member on host " + options.host);
  if (!options.until_exit.empty() && std::none_of(members.begin(), members.end(),
                                                  [&](const Member& m) { return m.spec.name == options.until_exit; })) {
    throw std::runtime_error("--until-exit " + options.until_exit + ": no such member");
  }
  return members;
}

GroupSupervisor::GroupSupervisor(const GroupSpec& group, SupervisorOptions options)
    : group_(group),
      options_(std::move(options)),
      members_(SelectMembers(group_, options_)),
      report_(group, options_.host) {}

// An exception out of Run (the bus, memory) still stops the members in
// order rather than leaving them to the launcher's death signal.
GroupSupervisor::~GroupSupervisor() { StopAll(); }

void GroupSupervisor::Start(Member& m) {
  m.pid = StartMember(m.spec, MemberArgv(m.spec, group_, options_.session_id, options_.bin_dir));
  std::fprintf(stderr, "edsp-launch: %-16s started  pid %d\n", m.spec.name.c_str(), m.pid);
}

void GroupSupervisor::StartAll(const std::function<bool()>& stop) {
  for (Member& m : members_) {
    if (stop()) break;
    Start(m);
    std::this_thread::sleep_for(std::chrono::milliseconds(m.spec.start_delay_ms));
  }
}

void GroupSupervisor::OnExit(Member& m, int status) {
  m.pid = -1;
  m.freeze.Forget();
  std::fprintf(stderr, "edsp-launch: %-16s exited   (%s)\n", m.spec.name.c_str(), DescribeExit(status).c_str());
  const bool failed = ExitFailed(status);
  const bool was_stopping = stopping_;
  const ExitDecision d = DecideOnExit(m.spec, m.restarts, failed, m.spec.name == options_.until_exit, stopping_);
  stopping_ = d.stop_group;
  if (d.restart) {
    m.restart_at = Clock::now() + std::chrono::milliseconds(d.backoff_ms);
    ++m.restarts;
    std::fprintf(stderr, "edsp-launch: %-16s restart %d in %d ms\n", m.spec.name.c_str(), m.restarts, d.backoff_ms);
    report_.Fault(m.spec.name, fault_t::SEVERITY_ERROR,
                  fmt::format("exited ({}); restart {} in {} ms", DescribeExit(status), m.restarts, d.backoff_ms));
    return;
  }
  m.done = true;
  m.failed = d.failed_for_good;
  if (d.failed_for_good && !was_stopping) {
    report_.Fault(m.spec.name, fault_t::SEVERITY_ERROR,
                  fmt::format("exited ({}) for good; stopping the group", DescribeExit(status)));
  }
}

// Frozen and resumed members, from the process table.
void GroupSupervisor::WatchFreezes() {
  const std::int64_t now = UtimeNow();
  for (Member& m : members_) {
    if (m.pid <= 0) continue;
    const ProcessState state = ReadProcessState(m.pid);
    const double frozen_ms = static_cast<double>(m.freeze.frozen_for_us(now)) * 1e-3;
    switch (m.freeze.Observe(state, now)) {
      case FreezeWatch::Change::kFroze:
        std::fprintf(stderr, "edsp-launch: %-16s frozen   (stopped)\n", m.spec.name.c_str());
        report_.Fault(
            m.spec.name, fault_t::SEVERITY_ERROR,
            fmt::format("pid {} is stopped (SIGSTOP, or a tracer for over a second): frozen, not running", m.pid));
        break;
      case FreezeWatch::Change::kResumed:
        std::fprintf(stderr, "edsp-launch: %-16s resumed  after %.0f ms\n", m.spec.name.c_str(), frozen_ms);
        report_.Fault(m.spec.name, fault_t::SEVERITY_INFO,
                      fmt::format("pid {} runs again after {:.0f} ms frozen", m.pid, frozen_ms));
        break;
      case FreezeWatch::Change::kNone: break;
    }
  }
}

bool GroupSupervisor::Healthy() const {
  return std::none_of(members_.begin(), members_.end(),
                      [](const Member& m) { return m.freeze.frozen() || (m.pid < 0 && !m.done); });
}

bool GroupSupervisor::Step() {
  int status = 0;
  pid_t pid;
  while ((pid = ::waitpid(-1, &status, WNOHANG)) > 0) {
    for (Member& m : members_) {
      if (m.pid == pid) OnExit(m, status);
    }
  }
  for (Member& m : members_) {
    if (!stopping_ && m.pid < 0 && !m.done && Clock::now() >= m.restart_at) {
      Start(m);
      if (m.restarts > 0) report_.Fault(m.spec.name, fault_t::SEVERITY_INFO, fmt::format("restarted as pid {}", m.pid));
    }
  }
  WatchFreezes();
  report_.Tick(Healthy());
  return !stopping_;
}

void GroupSupervisor::StopAll() {
  for (auto it = members_.rbegin(); it != members_.rend(); ++it) {
    if (it->pid <= 0) continue;
    const char* how = StopMember(it->pid);
    std::fprintf(stderr, "edsp-launch: %-16s stopped  (%s)\n", it->spec.name.c_str(), how);
    it->pid = -1;
  }
}

bool GroupSupervisor::failed() const {
  return std::any_of(members_.begin(), members_.end(), [](const Member& m) { return m.failed; });
}

int GroupSupervisor::Run(std::chrono::duration<double> duration, const std::function<bool()>& stop) {
  std::fprintf(stderr, "edsp-launch: group %s, session %lld, %zu members\n", group_.name.c_str(),
               static_cast<long long>(options_.session_id), members_.size());
  StartAll(stop);
  const auto started = Clock::now();
  auto last_step = started;
  for (;;) {
    const auto step_start = Clock::now();
    report_.RecordStepInterval(step_start - last_step);
    last_step = step_start;
    const bool go_on = Step();
    if (!go_on || stop()) break;
    if (duration.count() > 0.0 && Clock::now() - started >= duration) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  StopAll();
  for (const Member& m : members_) {
    if (m.failed) std::fprintf(stderr, "edsp-launch: %s failed\n", m.spec.name.c_str());
  }
  return failed() ? 1 : 0;
}

}  // namespace edsp
