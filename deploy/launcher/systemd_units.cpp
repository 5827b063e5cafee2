#include "systemd_units.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/node/node_options.h"

namespace edsp {

namespace {

// systemd unit names take [A-Za-z0-9:_.\-]; edsp names stay plain.
void CheckUnitName(const std::string& name, const std::string& what) {
  const bool plain = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!plain)
    throw std::runtime_error(
        fmt::format("{} \"{}\" cannot name a systemd unit (letters, digits, _ and - only)", what, name));
}

std::string Absolute(const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  char* resolved = ::realpath(path.c_str(), nullptr);
  if (resolved == nullptr) throw std::runtime_error(path + ": cannot resolve the group file's path");
  std::string out(resolved);
  std::free(resolved);
  return out;
}

const char* SystemdRestart(RestartPolicy policy) {
  switch (policy) {
    case RestartPolicy::kNever: return "no";
    case RestartPolicy::kOnFailure: return "on-failure";
    case RestartPolicy::kAlways: return "always";
  }
  return "on-failure";
}

std::string Unit(const std::string& instance) { return "edsp@" + instance + ".service"; }

std::string DropIn(const GroupSpec& group, const MemberSpec& m, const MemberSpec* before, const std::string& group_file,
                   const std::string& root, const std::string& bin_dir) {
  std::string unit = fmt::format(
      "# Written by edsp-launch --write-units from {0}: member {1} of group {2} on host {3}.\n"
      "[Unit]\nDescription=edsp {2}: {1} ({3})\nPartOf=edsp-{2}.target\n"
      "StartLimitIntervalSec=60\nStartLimitBurst={4}\n",
      group_file, m.name, group.name, m.host, m.max_restarts + 1);
  if (before != nullptr) unit += fmt::format("After={}\n", Unit(MemberInstance(group, *before)));
  for (const std::string& r : m.requires_members) {
    const std::string required = Unit(fmt::format("{}.{}", group.name, r));
    unit += fmt::format("Requires={0}\nAfter={0}\n", required);
  }
  unit += fmt::format(
      "\n[Service]\nEnvironment=EDSP_ROOT={0} EDSP_BIN_DIR={1} EDSP_GROUP_FILE={2} EDSP_MEMBER={3}\n"
      "WorkingDirectory={0}\nRestart={4}\n",
      root, bin_dir, group_file, m.name, SystemdRestart(m.restart));
  // The launcher's start_delay_ms: the next member (After= this one) starts
  // once this one has had that long to come up.
  if (m.start_delay_ms > 0) unit += fmt::format("ExecStartPost=/bin/sleep {:.3f}\n", m.start_delay_ms * 1e-3);
  return unit;
}

}  // namespace

std::string MemberInstance(const GroupSpec& group, const MemberSpec& member) { return group.name + "." + member.name; }

std::vector<UnitFile> MemberUnits(const GroupSpec& group, const std::string& host, const std::string& root,
                                  const std::string& bin_dir) {
  CheckUnitName(group.name, "group name");
  const std::string group_file = Absolute(group.path);
  std::vector<UnitFile> units;
  std::string wants;
  const MemberSpec* before = nullptr;
  for (const MemberSpec& m : group.members) {
    if (m.host != host) continue;
    CheckUnitName(m.name, "member name");
    const std::string instance = MemberInstance(group, m);
    units.push_back({Unit(instance) + ".d/10-edsp-member.conf", DropIn(group, m, before, group_file, root, bin_dir)});
    wants += " " + Unit(instance);
    before = &m;
  }
  if (units.empty()) throw std::runtime_error(fmt::format("{}: no member on host {}", group.path, host));
  units.push_back({fmt::format("edsp-{}.target", group.name),
                   fmt::format("# Written by edsp-launch --write-units from {0}: group {1}, host {2}.\n"
                               "[Unit]\nDescription=edsp group {1} on host {2}\nWants={3}\n"
                               "After=network-online.target time-sync.target\n\n"
                               "[Install]\nWantedBy=multi-user.target\n",
                               group_file, group.name, host, wants.substr(1))});
  return units;
}

void WriteMemberUnits(const GroupSpec& group, const std::string& host, const std::string& dir, const std::string& root,
                      const std::string& bin_dir) {
  if (host.empty()) throw std::runtime_error("--write-units needs --host: units are written per machine");
  namespace fs = std::filesystem;
  const fs::path template_path = fs::path(root) / "deploy/systemd/edsp@.service";
  if (!fs::exists(template_path))
    throw std::runtime_error(template_path.string() + ": no unit template there (--root)");
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

}  // namespace edsp
