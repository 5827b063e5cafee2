// The planner's motion service on the live sim group, driven by edsp-ctl as
// an operator's script drives it: work frames, a pivot, absolute and
// relative moves and a jog that each end on target, a check that refuses a path,
// bad input refused by name, a halt mid-move that `wait` reports (exit 4),
// status as JSON; then the requests of that log replayed onto another live
// group move nothing.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "group_watch.h"
#include "sim_group_harness.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

struct CtlResult {
  int exit_code = -1;
  std::string out, err;
};

// edsp-ctl on the group's bus. The waits are the machine's, not what is
// tested: a loaded CI host may take seconds to answer.
// The common options after the command, or before it (as git users type them).
CtlResult Ctl(const std::string& dir, const std::string& args, bool options_first = false) {
  static int n = 0;
  const std::string out = fmt::format("{}/ctl{}.out", dir, ++n), err = fmt::format("{}/ctl{}.err", dir, n);
  const std::string common = fmt::format("--answer-timeout-s 30 --group {}/group.toml", dir);
  const int status = std::system(fmt::format("{} {} {} >{} 2>{}", BuiltProgram("edsp-ctl"),
                                             options_first ? common : args, options_first ? args : common, out, err)
                                     .c_str());
  CtlResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  for (auto [path, text] : {std::pair{out, &r.out}, std::pair{err, &r.err}}) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    *text = s.str();
  }
  return r;
}

// The idle planner ends 6 s after the last motion ends. The script is of the
// service, not of holding: the nodes wait out a stall of the whole host of
// up to 250 ms (one over 50 ms latches the bridge mid-move, a correct hold).
constexpr const char* kIdlePlanner = R"("--exit-after-hold-s", "6")";

// edsp-ctl's --json output; a failure naming the output, never an abort, when it is none.
nlohmann::json Parsed(const std::string& out) {
  nlohmann::json parsed = nlohmann::json::parse(out, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object()) {
    ADD_FAILURE() << "edsp-ctl printed no JSON object: \"" << out << "\"";
    return nlohmann::json::object();
  }
  return parsed;
}

TEST(MotionServiceGroup, AnOperatorsScriptThroughEdspCtl) {
  nlohmann::json final_status;
  int moves_on_target = 0;
  const GroupRun run = LaunchSimGroup(
      "motion-script", "signed", kIdlePlanner,
      [&](const std::string& dir) {
        GroupWatch watch(kGroupLcmUrl, "");
        watch.WaitForSetpoint([](const pose_setpoint_t& s) { return s.session_id == 77; }, std::chrono::seconds(60));
        const CtlResult idle = Ctl(dir, "status --json", true);
        ASSERT_EQ(idle.exit_code, 0) << idle.err;
        EXPECT_EQ(Parsed(idle.out)["state"], "idle") << idle.out;
        ASSERT_EQ(Ctl(dir, "frame fixture --pose 0.05,-0.02,1.55,0,0,0.3").exit_code, 0);
        ASSERT_EQ(Ctl(dir, "pivot --point 0,0,0.3").exit_code, 0);
        for (const char* move :
             {"move --pose 0.02,0,1.53,0,0,0", "move --relative --frame fixture --pose 0,0,0,0.02,0,0",
              "move --frame home --pose=-0.01,0.01,0,0,0,0.02", "move --frame fixture --pose 0,0,0,0,0,0",
              "move --relative --pose 0,0,-0.01,0,0.01,0 --speed-m-s 0.05",
              "jog --axis yaw --step=-0.005 --frame fixture"}) {
          const CtlResult r = Ctl(dir, std::string(move) + " --timeout-s 60");
          EXPECT_EQ(r.exit_code, 0) << move << ": " << r.err;
          moves_on_target += r.exit_code == 0;
        }
        const CtlResult check = Ctl(dir, "check --pose 0,0,3.0,0,0,0 --json");
        EXPECT_EQ(check.exit_code, 2) << check.err;
        EXPECT_EQ(Parsed(check.out)["accepted"], false) << check.out;
        EXPECT_EQ(Parsed(check.out)["code"], "out_of_limits") << check.out;
        EXPECT_NE(check.err.find("outside the workspace"), std::string::npos) << check.err;
        EXPECT_EQ(Ctl(dir, "move --pose nan,0,1.5,0,0,0").exit_code, 1);
        const CtlResult frame = Ctl(dir, "move --frame nowhere --pose 0,0,0,0,0,0");
        EXPECT_EQ(frame.exit_code, 2);
        EXPECT_NE(frame.err.find("unknown frame \"nowhere\""), std::string::npos) << frame.err;
        EXPECT_EQ(Ctl(dir, "move --pose 0,0,1.5,0,0,0 --speed-m-s 1000").exit_code, 2);
        const CtlResult jog = Ctl(dir, "jog --axis x --step 0.02 --json");
        EXPECT_EQ(jog.exit_code, 2) << jog.err;
        EXPECT_NE(jog.err.find("beyond 0.01 m"), std::string::npos) << jog.err;
        EXPECT_EQ(Parsed(jog.out)["code"], "invalid") << jog.out;
        ASSERT_EQ(Ctl(dir, "move --pose 0.25,0,1.5,0,0,0 --no-wait").exit_code, 0);
        ASSERT_EQ(Ctl(dir, "halt").exit_code, 0);
        const CtlResult wait = Ctl(dir, "wait --timeout-s 30");
        EXPECT_EQ(wait.exit_code, 4) << wait.err;
        const CtlResult status = Ctl(dir, "status --json");
        ASSERT_EQ(status.exit_code, 0) << status.err;
        final_status = Parsed(status.out);
      },
      77, kDefaultConfig, kStallTolerantStaleMs);
  ASSERT_EQ(run.exit_code, 0);
  EXPECT_EQ(moves_on_target, 6);
  ASSERT_TRUE(final_status.is_object());
  EXPECT_EQ(final_status["state"], "holding") << final_status.dump();
  EXPECT_EQ(final_status["last_end"], "halted");
  EXPECT_EQ(final_status["pose_commanded"].size(), 6u);
  EXPECT_EQ(final_status["pivot"][2].get<double>(), 0.3);
  const double halted_at = final_status["pose_commanded"][0].get<double>();
  EXPECT_GT(halted_at, -0.02) << "it moved toward 0.25 before the halt";
  EXPECT_LT(halted_at, 0.25) << "and stopped short of it";
  // The rig's truth, settled, is where the halted move holds.
  const auto truths = LoggedMessages<rig_truth_t>(run.log_path, "EDSP_RIG_TRUTH");
  ASSERT_FALSE(truths.empty());
  EXPECT_NEAR(truths.back().pose[0], halted_at, 1e-6);
  // Every request, reply and status was recorded.
  EXPECT_GE(LoggedMessages<motion_request_t>(run.log_path, "EDSP_MOTION_REQUEST").size(), 12u);
  EXPECT_GE(LoggedMessages<motion_reply_t>(run.log_path, "EDSP_MOTION_REPLY").size(), 12u);
  EXPECT_GT(LoggedMessages<motion_status_t>(run.log_path, "EDSP_MOTION_STATUS").size(), 500u) << "50 Hz";

  // The same requests replayed onto another live group of the same session
  // (a log played back by mistake): stale, they move nothing.
  const std::string dir = run.dir;
  std::ofstream(dir + "/home.csv") << "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n"
                                   << "0,0,0,1.511,0,0,0\n8,0,0,1.511,0,0,0\n";
  const GroupRun live = LaunchSimGroup(
      "motion-replayed", "signed", fmt::format(R"("--csv", "{}/home.csv", "--exit-after-hold-s", "0")", dir),
      [&](const std::string&) {
        GroupWatch watch(kGroupLcmUrl, "");
        watch.WaitForSetpoint([](const pose_setpoint_t& s) { return s.session_id == 77; }, std::chrono::seconds(60));
        std::system(("lcm-logplayer -s 4 -e 'EDSP_MOTION_REQUEST' -l 'udpm://239.255.76.67:7667?ttl=0' " +
                     run.log_path + " >/dev/null 2>&1")
                        .c_str());
      },
      77, kDefaultConfig, kStallTolerantStaleMs);
  ASSERT_EQ(live.exit_code, 0);
  const auto replies = LoggedMessages<motion_reply_t>(live.log_path, "EDSP_MOTION_REPLY");
  EXPECT_FALSE(replies.empty()) << "the replayed requests reached the planner";
  for (const motion_reply_t& r : replies) {
    EXPECT_FALSE(r.accepted) << r.reason;
    EXPECT_NE(r.reason.find("replayed"), std::string::npos) << r.reason;
  }
  const Vector6 home = PlatformModel(Huang2021Config()).home_pose().ToVector();
  double furthest = 0.0;
  for (const rig_truth_t& t : LoggedMessages<rig_truth_t>(live.log_path, "EDSP_RIG_TRUTH")) {
    for (int k = 0; k < 6; ++k) furthest = std::max(furthest, std::abs(t.pose[k] - home(k)));
  }
  EXPECT_LT(furthest, 1e-6) << "a replayed request moved the platform";
}

}  // namespace
}  // namespace edsp
