#pragma once
// The one error of every config file edsp reads (the platform's, the rig's
// effects, the drives', a group file with its routes): its message names the
// file, the line, the [section] key and the value that is wrong.

#include <stdexcept>

namespace edsp {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace edsp
