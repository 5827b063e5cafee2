#pragma once
// The launcher's reading of a process-group file: the one parser of group
// files (edsp/node/group_file.h: GroupSpec, MemberSpec, ...), with member
// args expanded from the launcher's environment.

#include <string>

#include "edsp/node/group_file.h"

namespace edsp {

// ReadGroupFile with the launcher's environment for ${NAME} and
// ${NAME:-default} in member args (e.g. `deploy/edsp demo` sets the PR mode
// and log directory per run); an unset NAME without a default is an error,
// and so is a file without members (a reader of routes takes one: edsp-ctl,
// a node). Throws std::runtime_error naming the file, line and key.
GroupSpec LoadGroupFile(const std::string& path);

}  // namespace edsp
