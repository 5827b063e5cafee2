#include "sim_group_harness.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/logger/log_summary.h"

namespace edsp::test_support {

GroupRun LaunchSimGroup(const std::string& name, const std::string& pr_mode,
                        const std::string& planner_args,
                        const std::function<void(const std::string& dir)>& during,
                        std::int64_t session_id) {
  const std::string dir = fmt::format("/tmp/edsp_group_test_{}_{}", ::getpid(), name);
  std::system(("mkdir -p " + dir).c_str());
  GroupRun run;
  run.log_path = dir + "/run.lcmlog";
  std::ofstream(dir + "/group.toml") << fmt::format(R"(
[group]
name = "{0}"
config = "{1}/config/huang2021.toml"
session_id = {6}
[transport]
shm_prefix = "edsp.test.{2}.{0}"
[[member]]
name = "rig"
command = "edsp-rig"
args = ["--tracker-noise-m", "0"]
start_delay_ms = 200
[[member]]
name = "actuator_bridge"
command = "edsp-actuator-bridge"
start_delay_ms = 100
[[member]]
name = "kinematics"
command = "edsp-kinematics"
args = ["--pr-mode", "{3}"]
[[member]]
name = "logger"
command = "edsp-logger"
args = ["--output", "{4}"]
start_delay_ms = 300
[[member]]
name = "planner"
command = "edsp-planner"
args = [{5}]
restart = "never"
)",
                                                    name, EDSP_SOURCE_DIR, ::getpid(), pr_mode,
                                                    run.log_path, planner_args, session_id);
  const std::string command = fmt::format("{} {}/group.toml --until-exit planner --duration-s 120 2>{}/launch.err",
                                          EDSP_LAUNCH_BINARY, dir, dir);
  std::thread action;
  if (during) action = std::thread([&] { during(dir); });
  const int status = std::system(command.c_str());
  if (action.joinable()) action.join();
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}


void ExpectCleanRun(const GroupRun& run) {
  ASSERT_EQ(run.exit_code, 0) << "edsp-launch failed; see " << run.log_path << "/../launch.err";
  const LogSummary summary = SummarizeLog(run.log_path);
  EXPECT_EQ(summary.channels.count("EDSP_FAULT"), 0u) << "faults were raised: edsp-log faults " << run.log_path;
  const ChannelSummary& commands = summary.channels.at("EDSP_LEG_COMMAND");
  EXPECT_GT(commands.messages, 10000);
  EXPECT_NEAR(commands.rate_hz(), 1000.0, 20.0);
  // Loss on loopback multicast on this loaded 2-core machine: usually none,
  // occasionally one burst of up to ~30 ms (open in the multi-host issue,
  // which requires zero). Bounded at 1% so a broken logger or a systematic
  // loss still fails, while that known burst does not make the suite flaky.
  for (const char* channel : {"EDSP_LEG_COMMAND", "EDSP_SETPOINT", "EDSP_TRACKER"}) {
    const ChannelSummary& c = summary.channels.at(channel);
    EXPECT_LE(c.seq_gaps, c.messages / 100) << channel;
    ::testing::Test::RecordProperty(std::string(channel) + "_seq_gaps", static_cast<int>(c.seq_gaps));
  }
  EXPECT_GT(summary.channels.at("EDSP_CONFIG").messages, 5);
}

}  // namespace edsp::test_support
