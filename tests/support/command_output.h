#pragma once
// Runs a command line through the shell as a user would and keeps what it
// printed on stdout and stderr, and its exit code (-1 if it did not exit).

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace edsp::test_support {

struct CommandOutput {
  int exit_code = -1;
  std::string text;  // stdout and stderr
};

inline CommandOutput RunCommand(const std::string& command_line) {
  CommandOutput out;
  FILE* pipe = ::popen((command_line + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return out;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) out.text += buffer.data();
  const int status = ::pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

}  // namespace edsp::test_support
