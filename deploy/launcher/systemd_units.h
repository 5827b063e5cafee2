#pragma once
// The systemd units that run one host's members of a group: an instance
// edsp@<group>.<member>.service of the template deploy/systemd/edsp@.service
// per member, each with a drop-in saying which group file and member it runs,
// its restart policy, and its place in the start order (After= the member
// before it on this host, Requires= what the member's `requires` names), and
// edsp-<group>.target that wants them all. docs/multihost.md.

#include <string>
#include <vector>

#include "group_file.h"

namespace edsp {

struct UnitFile {
  std::string path;  // relative to the unit directory
  std::string text;
};

// `root` is the edsp checkout on the host (the template's EDSP_ROOT); the
// group file path is made absolute. Throws std::runtime_error if no member
// is on `host` or a name cannot be a unit name.
std::vector<UnitFile> MemberUnits(const GroupSpec& group, const std::string& host, const std::string& root,
                                  const std::string& bin_dir);

// Writes MemberUnits and the template (from `root`) into `dir`, printing
// each path on stdout. Throws std::runtime_error naming what is missing
// (--host, the template) or the file it cannot write.
void WriteMemberUnits(const GroupSpec& group, const std::string& host, const std::string& dir, const std::string& root,
                      const std::string& bin_dir);

// The instance name of a member: "<group>.<member>".
std::string MemberInstance(const GroupSpec& group, const MemberSpec& member);

}  // namespace edsp
