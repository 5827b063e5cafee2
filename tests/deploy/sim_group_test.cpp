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
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {
namespace {

struct GroupRun {
  int exit_code = -1;
  std::string log_path;
};

constexpr const char* kDefaultPlannerArgs =
    R"("--motions", "Lz,Rz", "--stops", "3", "--dwell-s", "0.6", "--max-speed-m-s", "0.25",
        "--max-speed-rad-s", "0.5", "--exit-after-hold-s", "0.3")";

GroupRun LaunchSimGroup(const std::string& name, const std::string& pr_mode,
                        const std::string& planner_args = kDefaultPlannerArgs,
                        const std::function<void(const std::string& dir)>& during = {},
                        std::int64_t session_id = 77) {
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

struct DwellEnd {
  std::string segment;
  Pose target;
  double miss_m;
};

// The last tracker sample of every dwell against the target's point A.
std::vector<DwellEnd> DwellEnds(const std::string& log_path, const PlatformModel& model) {
  LogReader reader(log_path);
  LogEvent event;
  std::vector<DwellEnd> ends;
  pose_setpoint_t previous{};
  bool have_previous = false;
  tracker_point_t last_tracker{};
  bool have_tracker = false;
  while (reader.Next(&event)) {
    const int size = static_cast<int>(event.data.size());
    if (event.channel == "EDSP_TRACKER") {
      tracker_point_t t;
      if (t.decode(event.data.data(), 0, size) >= 0) {
        last_tracker = t;
        have_tracker = true;
      }
    } else if (event.channel == "EDSP_SETPOINT") {
      pose_setpoint_t sp;
      if (sp.decode(event.data.data(), 0, size) < 0) continue;
      if (have_previous && have_tracker && sp.segment != previous.segment &&
          previous.trajectory.find("/dwell") != std::string::npos) {
        Vector6 q;
        for (int k = 0; k < 6; ++k) q(k) = previous.pose[k];
        const Vector3 target = model.ObservationPoint(Pose::FromVector(q));
        const Vector3 measured(last_tracker.point_m[0], last_tracker.point_m[1], last_tracker.point_m[2]);
        ends.push_back({previous.trajectory, Pose::FromVector(q), (measured - target).norm()});
      }
      previous = sp;
      have_previous = true;
    }
  }
  EXPECT_FALSE(reader.damaged());
  return ends;
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

// One signed run serves several tests.
class SignedSimGroup : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { run_ = new GroupRun(LaunchSimGroup("signed", "signed")); }
  static void TearDownTestSuite() { delete run_; }
  static GroupRun* run_;
};
GroupRun* SignedSimGroup::run_ = nullptr;

TEST_F(SignedSimGroup, SignedCompensationSettlesPointAWithin5umAtEveryDwell) {
  const GroupRun& run = *run_;
  ExpectCleanRun(run);
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

TEST_F(SignedSimGroup, ReplayedThroughLcmLogplayerAFreshKinematicsNodeReproducesTheCommands) {
  ASSERT_EQ(run_->exit_code, 0);
  const std::string dir = run_->log_path.substr(0, run_->log_path.rfind('/'));
  const std::string url = "udpm://239.255.76.67:7668?ttl=0&recv_buf_size=4194304";
  const std::string replayed = dir + "/replayed.lcmlog";
  const std::string bin = std::string(EDSP_LAUNCH_BINARY).substr(0, std::string(EDSP_LAUNCH_BINARY).rfind('/'));
  // Kinematics and a logger on their own port; then the recorded setpoints.
  const std::string script = fmt::format(
      "{0}/edsp-kinematics --replay --session-id 77 --config {1}/config/huang2021.toml --lcm-url '{2}' & K=$!; "
      "{0}/edsp-logger --channels EDSP_LEG_COMMAND --output {3} --lcm-url '{2}' & L=$!; sleep 0.5; "
      "lcm-logplayer -s 2 -e EDSP_SETPOINT -l '{2}' {4} >/dev/null; sleep 0.5; kill -INT $K $L; wait",
      bin, EDSP_SOURCE_DIR, url, replayed, run_->log_path);
  // system() runs the script in sh -c itself: no nested shell, so $! is ours.
  ASSERT_EQ(std::system(("{ " + script + "; } 2>" + dir + "/replay.err").c_str()), 0);
  const auto recorded = CommandsBySetpoint(run_->log_path);
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

TEST(SimGroup, WithoutCompensationMissesByThePredictedPrError) {
  const GroupRun run = LaunchSimGroup("none", "none");
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

TEST(SimGroup, KinematicsKilledMidMotionIsRestartedWhileTheBridgeHolds) {
  const std::string planner = R"("--motions", "Lz", "--stops", "2", "--dwell-s", "1",
        "--max-speed-m-s", "0.25", "--exit-after-hold-s", "0.5")";
  const GroupRun run = LaunchSimGroup("sigkill", "signed", planner, [](const std::string& dir) {
    std::this_thread::sleep_for(std::chrono::seconds(2));  // mid-way through the first move
    std::system(("pkill -KILL -f 'edsp-kinematics .*" + dir + "/group.toml'").c_str());
  });
  ASSERT_EQ(run.exit_code, 0);
  const std::string dir = run.log_path.substr(0, run.log_path.rfind('/'));
  std::ifstream launch_err(dir + "/launch.err");
  std::ostringstream launch_text;
  launch_text << launch_err.rdbuf();
  const std::string launch = launch_text.str();
  EXPECT_NE(launch.find("kinematics       restart 1"), std::string::npos) << launch;

  // From the log: the bridge's stale fault, and the platform's true motion.
  LogReader reader(run.log_path);
  LogEvent event;
  std::int64_t hold_utime = -1, refused_until_rearm = 0;
  std::vector<std::pair<std::int64_t, Vector6>> truth;
  while (reader.Next(&event)) {
    const int size = static_cast<int>(event.data.size());
    if (event.channel == "EDSP_FAULT") {
      fault_t f{};
      if (f.decode(event.data.data(), 0, size) >= 0 && f.node == "actuator_bridge" &&
          f.code == static_cast<std::int32_t>(FaultCode::kStale)) {
        if (hold_utime < 0) hold_utime = f.utime;
        if (f.reason.find("re-arm required") != std::string::npos) ++refused_until_rearm;
      }
    } else if (event.channel == "EDSP_RIG_TRUTH") {
      rig_truth_t t{};
      if (t.decode(event.data.data(), 0, size) >= 0) {
        Vector6 q;
        for (int k = 0; k < 6; ++k) q(k) = t.pose[k];
        truth.emplace_back(t.utime, q);
      }
    }
  }
  ASSERT_GT(hold_utime, 0) << "the bridge never reported holding";
  double largest_step = 0.0, drift_after_hold = 0.0;
  Vector6 held = Vector6::Zero();
  bool have_held = false;
  for (std::size_t k = 1; k < truth.size(); ++k) {
    largest_step = std::max(largest_step, (truth[k].second - truth[k - 1].second).head<3>().norm());
    if (truth[k].first > hold_utime + 200000) {  // the servo has settled on the hold
      if (!have_held) held = truth[k].second;
      have_held = true;
      drift_after_hold = std::max(drift_after_hold, (truth[k].second - held).head<3>().norm());
    }
  }
  // A jump would be the ~25 mm the planner moved during the outage; servo
  // motion is at most ~0.25-0.5 mm per cycle (more when a loaded machine makes
  // the rig catch up a late cycle).
  EXPECT_LT(largest_step, 1e-3) << "no jump";
  ::testing::Test::RecordProperty("largest_step_um", static_cast<int>(largest_step * 1e6));
  ::testing::Test::RecordProperty("drift_after_hold_nm", static_cast<int>(drift_after_hold * 1e9));
  ASSERT_TRUE(have_held);
  EXPECT_LT(drift_after_hold, 1e-6) << "the platform stays where it was held (nobody re-armed)";
  EXPECT_GT(refused_until_rearm, 100) << "the restarted kinematics' commands must be refused";
}

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
  const GroupRun live = LaunchSimGroup(
      "guard-live", "signed", fmt::format(R"("--csv", "{}/home.csv", "--exit-after-hold-s", "0")", dir),
      [&](const std::string&) {
        std::this_thread::sleep_for(std::chrono::seconds(2));
        std::system(("lcm-logplayer -e 'EDSP_SETPOINT|EDSP_LEG_COMMAND' "
                     "-l 'udpm://239.255.76.67:7667?ttl=0' " + source.log_path + " >/dev/null 2>&1")
                        .c_str());
      },
      99);
  ASSERT_EQ(live.exit_code, 0);
  LogReader reader(live.log_path);
  LogEvent event;
  std::int64_t foreign_refused = 0, truth_samples = 0;
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
      ++truth_samples;
    }
  }
  EXPECT_GT(truth_samples, 5000);
  EXPECT_LT(furthest_from_home, 1e-6) << "the replayed session moved the live platform";
  // Thousands were refused; EDSP_FAULT carries a throttled summary of them
  // (one per channel and code every 100 ms), not a flood.
  EXPECT_GT(foreign_refused, 20) << "the replayed setpoints and commands must be refused";
  EXPECT_LT(foreign_refused, 400) << "faults must be throttled, not one per refused message";
}

}  // namespace
}  // namespace edsp
