#include "group_file.h"

#include <cstdlib>
#include <stdexcept>

namespace edsp {

namespace {
const char* Environment(const std::string& name) { return std::getenv(name.c_str()); }
}  // namespace

GroupSpec LoadGroupFile(const std::string& path) {
  GroupSpec group = ReadGroupFile(path, Environment);
  if (group.members.empty()) throw std::runtime_error(path + ": no [[member]] entries");
  return group;
}

}  // namespace edsp
