// edsp-launch: starts a process group, watches it, restarts crashed members
// with backoff, and stops it in reverse order on Ctrl-C (SIGINT → SIGTERM →
// SIGKILL). Exits non-zero if a member failed for good. A member that
// freezes (stopped by a signal), exits or restarts is reported on EDSP_FAULT
// (node "launcher"), and the launcher's EDSP_STATUS is STATE_FAULT meanwhile
// (GroupSupervisor, group_supervisor.h).
//   edsp-launch GROUP_FILE [--host NAME] [--session-id N] [--duration-s S]
//                          [--until-exit MEMBER] [--bin-dir DIR]
//   edsp-launch GROUP_FILE --member NAME      run one member in place (systemd units)
//   edsp-launch GROUP_FILE --host NAME --write-units DIR [--root DIR]
//                                             write that host's systemd units
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "edsp/node/runtime.h"
#include "group_file.h"
#include "group_supervisor.h"
#include "member_process.h"
#include "multicast_route.h"
#include "systemd_units.h"

namespace edsp {
namespace {

std::string SelfDirectory() {
  char self[4096] = {0};
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  const std::string path = n > 0 ? std::string(self, static_cast<std::size_t>(n)) : "./x";
  return path.substr(0, path.rfind('/'));
}

// In place of the launcher: the member's own program, as a systemd unit runs it.
int ExecOneMember(const GroupSpec& group, const std::string& name, std::int64_t session_id,
                  const std::string& bin_dir) {
  const auto spec =
      std::find_if(group.members.begin(), group.members.end(), [&](const MemberSpec& m) { return m.name == name; });
  if (spec == group.members.end()) throw std::runtime_error("--member " + name + ": no such member in " + group.path);
  CheckMulticastInterface(group, spec->host);
  ExecMember(*spec, MemberArgv(*spec, group, session_id, bin_dir));
  return 127;
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-launch: start, watch and stop an edsp process group"};
  std::string group_path, only_member, unit_dir, root;
  SupervisorOptions options;
  double duration_s = 0.0;
  app.add_option("group", group_path, "group file (TOML)")->required();
  app.add_option("--host", options.host, "start only the members on this host");
  app.add_option("--session-id", options.session_id, "session id (default: the file's, or a fresh one)");
  app.add_option("--duration-s", duration_s, "stop the group after this long (0: run until Ctrl-C)");
  app.add_option("--until-exit", options.until_exit, "stop the group when this member exits successfully");
  app.add_option("--bin-dir", options.bin_dir, "where the edsp programs are (default: beside edsp-launch)");
  app.add_option("--member", only_member, "run this one member in place of the launcher (systemd units)");
  app.add_option("--write-units", unit_dir, "write --host's systemd units into this directory, then exit");
  app.add_option("--root", root, "--write-units: the edsp checkout on that host (default: this one)");
  CLI11_PARSE(app, argc, argv);

  const GroupSpec group = LoadGroupFile(group_path);
  if (options.bin_dir.empty()) options.bin_dir = SelfDirectory();
  if (!unit_dir.empty()) {
    if (root.empty()) root = std::filesystem::absolute(options.bin_dir + "/../..").lexically_normal().string();
    if (root.size() > 1 && root.back() == '/') root.pop_back();
    WriteMemberUnits(group, options.host, unit_dir, root,
                     std::filesystem::absolute(options.bin_dir).lexically_normal().string());
    return 0;
  }
  if (options.session_id == 0) options.session_id = group.session_id;
  if (options.session_id == 0 && !only_member.empty()) {
    // Each member runs (and restarts) on its own: a session drawn per exec
    // would differ between them, and the bridge would refuse every command.
    throw std::runtime_error(group_path +
                             ": --member needs a fixed session: set [group] session_id (or pass --session-id)");
  }
  if (options.session_id == 0) options.session_id = (UtimeNow() / 1000) & 0x7fffffff;  // fresh per launch
  if (!only_member.empty()) return ExecOneMember(group, only_member, options.session_id, options.bin_dir);
  if (!options.host.empty()) CheckMulticastInterface(group, options.host);
  InstallStopSignals();
  GroupSupervisor supervisor(group, options);
  return supervisor.Run(std::chrono::duration<double>(duration_s), StopRequested);
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-launch", edsp::Run, argc, argv, 2); }
