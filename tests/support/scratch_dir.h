#pragma once
// Where a test process keeps what it writes (group files, logs, CSVs): one
// directory per process, <TempDir>/edsp_test_<pid>, removed at the end when
// every test the process ran passed, and kept (named on stderr) when one
// failed, so its logs are there to read.
//
// Why: the multi-process and diagnosis tests write 100-300 MB of logs each.
// Left behind by passing runs, they filled a long-lived CI machine's disk
// (75 GB after some fifty runs) until a later CI run failed on "disk full".

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace edsp::test_support {

inline std::string ScratchRoot() {
  static const std::string root = testing::TempDir() + "edsp_test_" + std::to_string(::getpid());
  return root;
}

// <root>/<name>, created (with its parents) if missing.
inline std::string ScratchDir(const std::string& name) {
  const std::string dir = ScratchRoot() + "/" + name;
  std::filesystem::create_directories(dir);
  return dir;
}

class ScratchCleanup : public testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    if (!std::filesystem::exists(ScratchRoot(), ignored)) return;
    if (!testing::UnitTest::GetInstance()->Passed()) {
      std::fprintf(stderr, "kept %s for inspection (a test failed)\n", ScratchRoot().c_str());
      return;
    }
    // error_code: a directory still mounted (the disk-full test's) or a file
    // a straggling child holds is not worth failing a passed run for.
    std::filesystem::remove_all(ScratchRoot(), ignored);
  }
};

// Registered once per test program, before RUN_ALL_TESTS, by every program
// that includes this header.
inline const bool kScratchCleanupRegistered = (testing::AddGlobalTestEnvironment(new ScratchCleanup), true);

}  // namespace edsp::test_support
