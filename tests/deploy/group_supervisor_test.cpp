// GroupSupervisor with real processes (sh): starts, restarts by policy with
// the backoff, stops the group on a failure for good or the --until-exit
// member's clean exit, and stops what runs in reverse order.
#include "group_supervisor.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "scratch_dir.h"

namespace edsp {
namespace {

// A group file of sh members on memq:// (the report goes nowhere).
GroupSpec ShGroup(const std::string& name, const std::string& members_toml) {
  const std::string path = test_support::ScratchDir("supervisor") + "/" + name + ".toml";
  std::ofstream(path) << "[group]\nname = \"" << name << "\"\n[transport]\nlcm_url = \"memq://\"\n" << members_toml;
  return LoadGroupFile(path);
}

std::string ShMember(const std::string& name, const std::string& script, const std::string& restart, int max_restarts) {
  return "[[member]]\nname = \"" + name + "\"\ncommand = \"/bin/sh\"\nargs = [\"-c\", \"" + script +
         "\"]\nnode_options = false\nrestart = \"" + restart + "\"\nmax_restarts = " + std::to_string(max_restarts) +
         "\n";
}

double RunSeconds(GroupSupervisor& supervisor, int* exit_code, double limit_s = 20.0) {
  const auto start = std::chrono::steady_clock::now();
  *exit_code = supervisor.Run(std::chrono::duration<double>(limit_s), [] { return false; });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(GroupSupervisor, AMemberThatKeepsFailingIsRestartedWithBackoffThenStopsTheGroupFailed) {
  const std::string count = test_support::ScratchDir("supervisor") + "/starts";
  const GroupSpec group =
      ShGroup("failing", ShMember("steady", "exec sleep 30", "on-failure", 10) +
                             ShMember("crashy", "echo x >> " + count + "; exit 3", "on-failure", 2));
  GroupSupervisor supervisor(group, SupervisorOptions{"", 1, "/nonexistent", ""});
  int exit_code = -1;
  const double seconds = RunSeconds(supervisor, &exit_code);
  EXPECT_EQ(exit_code, 1);
  EXPECT_TRUE(supervisor.failed());
  std::ifstream starts(count);
  int lines = 0;
  for (std::string line; std::getline(starts, line);) ++lines;
  EXPECT_EQ(lines, 3) << "started once and restarted twice (max_restarts = 2)";
  // Backoffs of 100 and 200 ms before the restarts; then the steady member
  // is stopped by SIGINT at once: far below the 20 s limit.
  EXPECT_GE(seconds, 0.3);
  EXPECT_LT(seconds, 15.0) << "the group did not stop when a member failed for good";
}

TEST(GroupSupervisor, TheUntilExitMembersCleanExitStopsTheGroupWithoutFailure) {
  const GroupSpec group = ShGroup("until", ShMember("steady", "exec sleep 30", "always", 10) +
                                               ShMember("planner", "sleep 0.2; exit 0", "never", 0));
  GroupSupervisor supervisor(group, SupervisorOptions{"", 1, "/nonexistent", "planner"});
  int exit_code = -1;
  const double seconds = RunSeconds(supervisor, &exit_code);
  EXPECT_EQ(exit_code, 0);
  EXPECT_FALSE(supervisor.failed());
  EXPECT_LT(seconds, 15.0) << "the run did not end with the --until-exit member";
}

std::string RefusalOf(const GroupSpec& group, const SupervisorOptions& options) {
  try {
    GroupSupervisor supervisor(group, options);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(GroupSupervisor, RefusesAHostWithoutMembersAndAnUnknownUntilExitMember) {
  const GroupSpec group = ShGroup("refused", ShMember("steady", "exec sleep 30", "always", 10));
  EXPECT_NE(RefusalOf(group, SupervisorOptions{"elsewhere", 1, "/nonexistent", ""}).find("no member on host elsewhere"),
            std::string::npos);
  EXPECT_NE(RefusalOf(group, SupervisorOptions{"", 1, "/nonexistent", "nobody"}).find("--until-exit nobody"),
            std::string::npos);
}

// Members stop in reverse start order (the rig, first up, last down: what
// feeds the drives goes before the drives): each notes its SIGINT.
TEST(GroupSupervisor, StopsTheMembersInReverseOrder) {
  const std::string order = test_support::ScratchDir("supervisor") + "/stop_order";
  auto member = [&](const std::string& name) {
    return ShMember(name, "trap 'echo " + name + " >> " + order + "; exit 0' INT; while :; do sleep 0.05; done",
                    "never", 0);
  };
  const GroupSpec group = ShGroup("order", member("first") + member("second") + member("third"));
  GroupSupervisor supervisor(group, SupervisorOptions{"", 1, "/nonexistent", ""});
  int exit_code = -1;
  RunSeconds(supervisor, &exit_code, 0.5);
  EXPECT_EQ(exit_code, 0);
  std::ifstream in(order);
  std::vector<std::string> stopped;
  for (std::string line; std::getline(in, line);) stopped.push_back(line);
  EXPECT_EQ(stopped, (std::vector<std::string>{"third", "second", "first"}));
}

}  // namespace
}  // namespace edsp
