#include "group_file.h"

#include <cstdlib>

namespace edsp {

namespace {
const char* Environment(const std::string& name) { return std::getenv(name.c_str()); }
}  // namespace

GroupSpec LoadGroupFile(const std::string& path) { return ReadGroupFile(path, Environment); }

}  // namespace edsp
