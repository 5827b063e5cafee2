#pragma once
// Where a test process keeps what it writes (group files, logs, CSVs): one
// fresh directory per process, /tmp/edsp_test_<pid>_XXXXXX, removed at the
// end when every test the process ran passed, and kept (named on stderr)
// when one failed, so its logs are there to read.
//
// Why: the multi-process and diagnosis tests write 100-300 MB of logs each.
// Left behind by passing runs, they filled a long-lived CI machine's disk
// (75 GB after some fifty runs) until a later CI run failed on "disk full".
// /tmp, not $TMPDIR: where deploy/edsp test checks for room.

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace edsp::test_support {

class ScratchCleanup : public testing::Environment {
 public:
  explicit ScratchCleanup(std::string root) : root_(std::move(root)) {}
  void TearDown() override {
    if (!testing::UnitTest::GetInstance()->Passed()) {
      std::fprintf(stderr, "kept %s for inspection (a test failed)\n", root_.c_str());
      return;
    }
    std::error_code error;
    std::filesystem::remove_all(root_, error);
    // Not worth failing a passed run for (a file a straggling child still
    // writes), but said: what is left takes room.
    if (error) std::fprintf(stderr, "could not remove all of %s: %s\n", root_.c_str(), error.message().c_str());
  }

 private:
  std::string root_;
};

// Created on first use, and its cleanup registered then (gtest tears down
// every environment registered by the end of the run).
inline std::string ScratchRoot() {
  static const std::string root = [] {
    std::string pattern = "/tmp/edsp_test_" + std::to_string(::getpid()) + "_XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create " + pattern);
    testing::AddGlobalTestEnvironment(new ScratchCleanup(pattern));
    return pattern;
  }();
  return root;
}

// <root>/<name>, created (with its parents) if missing.
inline std::string ScratchDir(const std::string& name) {
  const std::string dir = ScratchRoot() + "/" + name;
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace edsp::test_support
