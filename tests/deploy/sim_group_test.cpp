// The sim group as real processes (rig, actuator bridge, kinematics, logger,
// planner) started by edsp-launch inside a private network namespace. From
// the group's own log: with tracker noise off, point A settles within 5 µm
// of target at every dwell with signed compensation, and with mode none it
// misses by the PR error edsp-sim predicts; no faults, no lost commands.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "group_watch.h"
#include "sim_group_harness.h"
#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_summary.h"
#include <functional>
#include <sstream>
#include <map>
#include <thread>

#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/sim/paper_table.h"
#include "edsp/fault_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

void ExpectEveryDwellWithin5um(const GroupRun& run) {
  const PlatformModel model(Huang2021Config());
  const std::vector<DwellEnd> ends = DwellEnds(run.log_path, model);
  ASSERT_GE(ends.size(), 5u);  // Lz: 3 stops + home, Rz: 3 stops (+ home at the end)
  for (const DwellEnd& d : ends) EXPECT_LT(d.miss_m, 5e-6) << d.segment;
}

std::map<std::int64_t, leg_command_t> CommandsBySetpoint(const std::string& log_path) {
  LogReader reader(log_path);
  LogEvent event;
  std::map<std::int64_t, leg_command_t> commands;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_LEG_COMMAND") continue;
    leg_command_t c;
    if (c.decode(event.data.data(), 0, static_cast<int>(event.data.size())) >= 0) {
      commands[c.setpoint_seq] = c;
    }
  }
  return commands;
}

// Replayed through lcm-logplayer, a fresh kinematics node reproduces the commands.
void ExpectReplayReproducesTheCommands(const GroupRun& run) {
  const std::string dir = run.dir;
  const std::string replayed = dir + "/replayed.lcmlog";
  // The replay group as users run it: a fresh kinematics node and a logger on
  // their own port, fed the recorded setpoints by lcm-logplayer (a member).
  const std::string command = fmt::format(
      "cd {0} && EDSP_REPLAY_LOG={1} EDSP_LOG={2} {3} deploy/groups/replay.toml --session-id 77 "
      "--until-exit player --duration-s 120 2>{4}/replay.err",
      SourceDir(), run.log_path, replayed, BuiltProgram("edsp-launch"), dir);
  ASSERT_EQ(std::system(command.c_str()), 0) << "see " << dir << "/replay.err";
  const auto recorded = CommandsBySetpoint(run.log_path);
  const auto reproduced = CommandsBySetpoint(replayed);
  ASSERT_GT(recorded.size(), 10000u);
  std::size_t matched = 0, different = 0;
  for (const auto& [setpoint_seq, again] : reproduced) {
    const auto it = recorded.find(setpoint_seq);
    if (it == recorded.end()) continue;
    ++matched;
    for (int i = 0; i < 6; ++i) {
      if (again.command_length_m[i] != it->second.command_length_m[i] ||
          again.pr_correction_m[i] != it->second.pr_correction_m[i]) {
        ++different;
        break;
      }
    }
  }
  EXPECT_EQ(different, 0u) << "replayed commands must be bit-identical";
  EXPECT_GE(matched, recorded.size() * 99 / 100) << "replay lost more than 1% of the setpoints";
}

// One signed run checked twice, in one test: ctest runs each test in a
// process of its own, and the run takes 30 s of the suite.
TEST(SignedSimGroup, SettlesPointAWithin5umAtEveryDwellAndItsReplayReproducesTheCommands) {
  const GroupRun run = LaunchSimGroup("signed", "signed", test_support::kDefaultPlannerArgs, {}, 77,
                                      test_support::kDefaultConfig, test_support::kStallTolerantStaleMs);
  ExpectCleanRun(run);
  ASSERT_EQ(run.exit_code, 0);
  ExpectEveryDwellWithin5um(run);
  ExpectReplayReproducesTheCommands(run);
}

TEST(SimGroup, WithoutCompensationMissesByThePredictedPrError) {
  const GroupRun run = LaunchSimGroup("none", "none", test_support::kDefaultPlannerArgs, {}, 77,
                                      test_support::kDefaultConfig, test_support::kStallTolerantStaleMs);
  ExpectCleanRun(run);
  const PlatformModel model(Huang2021Config());
  double largest = 0.0;
  for (const DwellEnd& d : DwellEnds(run.log_path, model)) {
    const double predicted = PointAError(model, d.target, PrMode::kNone);
    EXPECT_NEAR(d.miss_m, predicted, 2e-6) << d.segment;
    largest = std::max(largest, predicted);
  }
  EXPECT_GT(largest, 1e-3);  // Rz ±30°: about 1.4 mm
}

// The kinematics node killed mid-motion (and every other node killed or
// frozen) is in fault_matrix_test.cpp.

TEST(SimGroup, ALogReplayedFromAnotherSessionMovesNothing) {
  // A recording of session 77 moving the platform ...
  const GroupRun source = LaunchSimGroup(
      "guard-source", "signed",
      R"("--motions", "Lz", "--stops", "2", "--dwell-s", "0.2", "--max-speed-m-s", "0.5", "--exit-after-hold-s", "0")");
  ASSERT_EQ(source.exit_code, 0);
  // ... replayed (setpoints and leg commands) onto a live session-99 group
  // whose own planner holds home.
  const std::string dir = source.log_path.substr(0, source.log_path.rfind('/'));
  std::ofstream(dir + "/home.csv") << "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n"
                                   << "0,0,0,1.511,0,0,0\n8,0,0,1.511,0,0,0\n";
  std::int64_t replay_start_utime = 0, replay_end_utime = 0;
  const GroupRun live = LaunchSimGroup(
      "guard-live", "signed", fmt::format(R"("--csv", "{}/home.csv", "--exit-after-hold-s", "0")", dir),
      [&](const std::string&) {
        // The live group up (its planner's setpoints flowing), however long
        // it took to start; then the replay.
        test_support::GroupWatch watch(test_support::kGroupLcmUrl, "");
        watch.WaitForSetpoint([](const pose_setpoint_t& s) { return s.session_id == 99; }, std::chrono::seconds(60));
        replay_start_utime = UtimeNow();
        std::system(("lcm-logplayer -e 'EDSP_SETPOINT|EDSP_LEG_COMMAND' "
                     "-l 'udpm://239.255.76.67:7667?ttl=0' " +
                     source.log_path + " >/dev/null 2>&1")
                        .c_str());
        replay_end_utime = UtimeNow();
      },
      99);
  ASSERT_EQ(live.exit_code, 0);
  LogReader reader(live.log_path);
  LogEvent event;
  std::int64_t foreign_refused = 0, last_truth_utime = 0, truth_during_replay = 0;
  std::int64_t first_seq = -1, last_seq = -1, previous_utime = 0, largest_gap_us = 0;  // of the truth in the replay
  double furthest_from_home = 0.0;
  const Vector6 home = PlatformModel(Huang2021Config()).home_pose().ToVector();
  while (reader.Next(&event)) {
    const int size = static_cast<int>(event.data.size());
    if (event.channel == "EDSP_FAULT") {
      fault_t f{};
      if (f.decode(event.data.data(), 0, size) >= 0 &&
          f.code == static_cast<std::int32_t>(FaultCode::kForeignSession)) {
        ++foreign_refused;
      }
    } else if (event.channel == "EDSP_RIG_TRUTH") {
      rig_truth_t t{};
      if (t.decode(event.data.data(), 0, size) < 0) continue;
      Vector6 q;
      for (int k = 0; k < 6; ++k) q(k) = t.pose[k];
      furthest_from_home = std::max(furthest_from_home, (q - home).cwiseAbs().maxCoeff());
      last_truth_utime = t.utime;
      if (t.utime >= replay_start_utime && t.utime <= replay_end_utime) {
        ++truth_during_replay;
        if (first_seq < 0) first_seq = t.seq;
        // A gap in the log is one where messages are missing (the seq
        // skips); a rig that published late on a loaded machine is no gap.
        if (previous_utime != 0 && t.seq > last_seq + 1) {
          largest_gap_us = std::max(largest_gap_us, t.utime - previous_utime);
        }
        last_seq = t.seq;
        previous_utime = t.utime;
      }
    }
  }
  // The platform was watched for as long as the replay and the live group
  // overlapped: the log holds nine in ten of what the rig published meanwhile
  // (its seq span: a rig on a loaded machine loses physics time, which is no
  // gap in the watch) and never lost 100 ms of it in one piece.
  const std::int64_t overlap_ms = (std::min(replay_end_utime, last_truth_utime) - replay_start_utime) / 1000;
  // The live planner holds home for 8 s from its first setpoint, when the
  // replay (seconds of a recorded motion) starts: they overlap by seconds.
  EXPECT_GT(overlap_ms, 1000) << "the live group ended before the replay had run";
  EXPECT_GT(truth_during_replay, (last_seq - first_seq + 1) * 9 / 10) << "the logger lost the platform's pose";
  EXPECT_GT(last_seq - first_seq, overlap_ms / 2) << "the rig published less than half the time";
  EXPECT_LT(largest_gap_us, 100000) << "the log lost the platform for " << largest_gap_us / 1000 << " ms";
  EXPECT_LT(furthest_from_home, 1e-6) << "the replayed session moved the live platform";
  // Thousands were refused; EDSP_FAULT carries a throttled summary of them
  // (one per channel and code every 100 ms), not a flood.
  EXPECT_GT(foreign_refused, 20) << "the replayed setpoints and commands must be refused";
  EXPECT_LT(foreign_refused, 400) << "faults must be throttled, not one per refused message";
}

}  // namespace
}  // namespace edsp
