// The sim-cueing group as real processes: a vehicle model's packets on UDP
// (edsp-cueing send) engage the platform through the planner (at home: no
// move to make), the brake is washed out onto the platform (the setpoints are the
// cueing source's, the rig moves back and tilts nose down), then disengage
// washes it home and parks it, and the run's log scores it (the packets the
// cueing took are on EDSP_VEHICLE); and a host on the bus (EDSP_VEHICLE) that
// falls silent has its platform washed home while still engaged, then an
// e-stop word holds it, while samples addressed to another session never
// engage it.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/kinematics/config.h"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/build_paths.h"
#include "edsp/node/runtime.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "group_watch.h"
#include "late_cycles.h"
#include "sim_group_harness.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

// The planner ends this long after the platform parked (or held after an
// e-stop). These tests are of the path, not of the holds (the planner's
// unit tests and the fault groups are): a stall of the whole host longer
// than 20 ms ends a cueing, one over 50 ms latches the bridge, correctly,
// so here the planner and the nodes wait out a stall of up to 250 ms.
constexpr int kCueStaleMs = kStallTolerantStaleMs;
constexpr std::int64_t kCueLeadUs = 10'000;  // how far the planner carries a cue, either way
const std::string kCueingPlanner = fmt::format(R"("--exit-after-hold-s", "2", "--cue-stale-ms", "{}")", kCueStaleMs);
constexpr std::int64_t kSession = 78;

constexpr char kToUdp[] = "--to 127.0.0.1:7400";

// edsp-cueing send to `to`: the group's socket (the test's private network),
// or its bus; its exit code.
int Send(const std::string& manoeuvre, const std::string& after, double lead_s, double tail_s,
         const std::string& sent_log = "", const std::string& to = kToUdp) {
  const std::string command =
      fmt::format("{} send --manoeuvre {} {} --lead-s {} --after {} --tail-s {}{}", BuiltProgram("edsp-cueing"),
                  manoeuvre, to, lead_s, after, tail_s, sent_log.empty() ? "" : " --sent-log " + sent_log);
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// edsp-cueing's JSON for `arguments` (--json added), kept in `dir` as `name`.
nlohmann::json CueingJson(const std::string& dir, const std::string& arguments, const std::string& name) {
  const std::string path = dir + "/" + name;
  EXPECT_EQ(std::system(fmt::format("{} {} --json > {}", BuiltProgram("edsp-cueing"), arguments, path).c_str()), 0)
      << arguments;
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// The run scored from its log (edsp-cueing score), held to the same brake
// scored offline (edsp-cueing offline: the manoeuvre's samples at 1 kHz
// through the washout, no process, no clock) over its own 10 s: the rest
// the window holds besides the brake adds no error, so the live RMS is the
// offline one spread over the longer window. The virtual rig follows its
// commands closely: what its rider felt is what the commands make one
// feel. The score's JSON, for what else a test checks.
nlohmann::json ExpectScoredAsTheBrakeOffline(const GroupRun& run) {
  const nlohmann::json score = CueingJson(
      run.dir, fmt::format("score --log {} --cueing {}", run.log_path, SourcePath("config/cueing.toml")), "score.json");
  const nlohmann::json offline =
      CueingJson(run.dir,
                 fmt::format("offline --config {} --cueing {} --manoeuvre {}", SourcePath("config/huang2021.toml"),
                             SourcePath("config/cueing.toml"), SourcePath("config/manoeuvres/braking.toml")),
                 "offline.json");
  EXPECT_EQ(score["session_id"], kSession);
  const double window_s = score["duration_s"], brake_s = offline["manoeuvres"][0]["duration_s"];
  EXPECT_GT(window_s, brake_s) << "the brake heard and followed, after the lead";
  if (score["real_from"] != "EDSP_RIG_TRUTH") {
    ADD_FAILURE() << "the real motion not scored from the rig's truth: " << score.dump();
    return score;
  }
  const double commanded = score["commanded"]["perception_error"], real = score["real"]["perception_error"];
  const double offline_spread =
      offline["manoeuvres"][0]["perception_error"].get<double>() * std::sqrt(brake_s / window_s);
  EXPECT_NEAR(commanded, offline_spread, 0.03 * offline_spread) << score.dump();
  EXPECT_NEAR(real, commanded, 0.02 * commanded) << score.dump();
  return score;
}

void WaitForTheGroup() {
  GroupWatch watch(kGroupLcmUrl, "");
  ASSERT_TRUE(watch.WaitForSetpoint([](const pose_setpoint_t& s) { return s.session_id == kSession; },
                                    std::chrono::seconds(60)));
}

// The shipped group, its cueing config found from the test's directory.
SimGroupExtras CueingGroup() {
  SimGroupExtras extras;
  extras.group = "sim-cueing";
  extras.edit = [](GroupFileEditor& group) { group.SetArg("cueing", "--cueing", SourcePath("config/cueing.toml")); };
  return extras;
}

Vector6 TruthPose(const rig_truth_t& truth) { return Eigen::Map<const Vector6>(truth.pose); }

// A setpoint that holds where the one before it was: the same pose, at rest.
bool IsHoldOf(const pose_setpoint_t& s, const pose_setpoint_t& before) {
  for (int k = 0; k < 6; ++k) {
    if (s.pose[k] != before.pose[k] || s.velocity[k] != 0.0 || s.acceleration[k] != 0.0) return false;
  }
  return true;
}

// The samples edsp-cueing send --sent-log wrote whose sequence a setpoint
// carries in `segments` (its low 31 bits, as the cueing writes it).
int SentFollowed(const std::string& sent_csv, const std::set<std::int32_t>& segments) {
  std::ifstream in(sent_csv);
  std::string line;
  std::getline(in, line);  // sequence,sent_utime
  int count = 0;
  long long sequence = 0, sent_utime = 0;
  char comma = 0;
  while (in >> sequence >> comma >> sent_utime) {
    count += static_cast<int>(segments.count(static_cast<std::int32_t>(sequence & 0x7fffffff)));
  }
  return count;
}

TEST(CueingGroup, ABrakeFromUdpIsWashedOntoThePlatformThenDisengageParksItAtHome) {
  const PlatformModel model(Huang2021Config());
  const Vector6 home = model.home_pose().ToVector();
  const GroupRun run = LaunchSimGroup(
      "cueing-brake", "signed", kCueingPlanner,
      [&](const std::string& dir) {
        WaitForTheGroup();
        // A short tail: once the word is seen the source washes out whether packets come or not.
        EXPECT_EQ(Send(SourcePath("config/manoeuvres/braking.toml"), "disengage", 3.0, 3.0, dir + "/sent.csv"), 0);
      },
      kSession, kDefaultConfig, kStallTolerantStaleMs, CueingGroup());
  ASSERT_EQ(run.exit_code, 0) << "the planner ended after the platform parked";
  EXPECT_EQ(FaultLines(run.log_path), "");

  const auto statuses = LoggedMessages<motion_status_t>(run.log_path, "EDSP_MOTION_STATUS");
  bool cueing = false;
  for (const motion_status_t& s : statuses) {
    cueing = cueing || (s.state == motion_status_t::STATE_CUEING && s.activity == "cueing edsp-cueing");
  }
  EXPECT_TRUE(cueing) << "the planner followed the cueing source";
  ASSERT_FALSE(statuses.empty());
  EXPECT_EQ(statuses.back().state, motion_status_t::STATE_HOLDING) << statuses.back().reason;

  // Every setpoint while cueing is one of the source's cues within the stale limit
  // carried to its time along the cue's velocity and acceleration, forward
  // or back (at most the 10 ms the bridge rides through): a cycle of the
  // planner that ran late may take a cue stamped after its tick. One near a cue
  // the logger lost (a stall of the whole host) cannot be checked. Once the
  // cueing ended, the hold at its last pose keeps its name (as a hold after
  // a move keeps the move's) until the parking move starts: at rest, where
  // the last setpoint was, and never followed by a cue again.
  const auto cues = LoggedMessages<pose_setpoint_t>(run.log_path, "EDSP_CUE_SETPOINT");
  int followed = 0, carried = 0, held = 0, unverified = 0, catching_up = 0;
  std::int64_t first_cueing_utime = 0, last_cueing_utime = 0;  // the stretch the planner followed the cueing
  std::set<std::int32_t> followed_segments;  // the vehicle packets the logged cueing setpoints came from
  std::size_t next = 0;                      // the first cue stamped more than the lead after the setpoint
  pose_setpoint_t previous{};
  for (const pose_setpoint_t& s : LoggedMessages<pose_setpoint_t>(run.log_path, "EDSP_SETPOINT")) {
    while (next < cues.size() && cues[next].utime <= s.utime + kCueLeadUs) ++next;
    const pose_setpoint_t before = std::exchange(previous, s);
    if (s.phase != pose_setpoint_t::PHASE_CUEING) continue;
    if (first_cueing_utime == 0) first_cueing_utime = s.utime;
    last_cueing_utime = s.utime;
    followed_segments.insert(s.segment);
    // Every cue up to the first after the setpoint's cycle in the log: none
    // the logger lost between the last one logged and the setpoint.
    bool found = false, logged_all = next == 0 || next == cues.size() || cues[next - 1].seq + 1 == cues[next].seq;
    for (std::size_t back = 1; back <= next && !found; ++back) {
      const pose_setpoint_t& c = cues[next - back];
      if (s.utime - c.utime > kCueStaleMs * 1000) break;
      logged_all = logged_all && (back == next || cues[next - back - 1].seq + 1 == c.seq);
      const double dt =
          std::clamp(static_cast<double>(s.utime - c.utime) * 1e-6, -kCueLeadUs * 1e-6, kCueLeadUs * 1e-6);
      double worst = 0.0;
      for (int k = 0; k < 6; ++k) {
        worst =
            std::max(worst, std::abs(c.pose[k] + c.velocity[k] * dt + 0.5 * c.acceleration[k] * dt * dt - s.pose[k]));
      }
      found = worst < 1e-9;
      carried += found && c.utime < s.utime - 1000;
    }
    if (held == 0 && found) {
      ++followed;
      continue;
    }
    if (held == 0 && !logged_all) {  // the cue it followed may be one the logger lost in a stall
      ++unverified;
      continue;
    }
    // Catching up after a stall (the cue carried to the tick farther than
    // the legs go in a cycle): a step toward it within the legs' speed.
    if (held == 0 && before.phase == pose_setpoint_t::PHASE_CUEING && s.utime > before.utime) {
      const Vector6 legs_step = (model.LegLengths(Pose::FromVector(Eigen::Map<const Vector6>(s.pose))) -
                                 model.LegLengths(Pose::FromVector(Eigen::Map<const Vector6>(before.pose))))
                                    .cwiseAbs();
      const double span_s = std::max(1e-3, static_cast<double>(s.utime - before.utime) * 1e-6);
      if (legs_step.maxCoeff() <= model.config().limits.leg_speed_max_m_s * span_s + 1e-6) {
        ++catching_up;
        continue;
      }
    }
    ASSERT_TRUE(before.phase == pose_setpoint_t::PHASE_CUEING && IsHoldOf(s, before))
        << "setpoint seq " << s.seq << (held == 0 ? " follows none of the cues before it" : " moves after the hold");
    ++held;
  }
  EXPECT_GT(followed, 10'000) << "10 s of the brake and its washout at 1 kHz";
  EXPECT_LT(held, 50) << "the parking move starts within a cycle or two of the disengage";
  EXPECT_LT(unverified, followed / 100) << "setpoints near a cue missing from the log";
  EXPECT_LT(catching_up, followed / 100) << "setpoints catching up after a stall";
  std::printf(
      "%d setpoints followed the cues, %d of them carried from one over a cycle old; %d caught up after a stall; %d "
      "held; %d unverified\n",
      followed, carried, catching_up, held, unverified);

  // The rig itself: surged back (−x) and tilted nose down (pitch > 0) by the brake, then parked at home.
  const auto truths = LoggedMessages<rig_truth_t>(run.log_path, "EDSP_RIG_TRUTH");
  ASSERT_FALSE(truths.empty());
  double least_x = 0.0, most_pitch = 0.0;
  for (const rig_truth_t& t : truths) {
    least_x = std::min(least_x, TruthPose(t)(0) - home(0));
    most_pitch = std::max(most_pitch, TruthPose(t)(4) - home(4));
  }
  EXPECT_LT(least_x, -0.005);
  EXPECT_GT(most_pitch, 0.01);
  EXPECT_LT((TruthPose(truths.back()) - home).head<3>().norm(), 50e-6);

  // Each vehicle sample traced from its sender to the drive write of a
  // command made from it, through the log (edsp-cueing delay): the samples
  // while engaged, nearly all (at 250 Hz against the cue's 1 kHz none is
  // overtaken), none sooner than the stack's phases allow: the cueing's
  // tick (800 µs into the millisecond) takes the packet, the planner's (at
  // 1000) the cue, the bridge's (at 1400) writes the command: 600 µs by the
  // phases (a little less as stamped: the ticks wake on their clock, the
  // stamps are another's), and never under the bridge's 400 µs behind the
  // planner, which a trace to a write before its command came would be (the
  // leg state's own stamp, its reading's instant, would give that), less
  // how late this run's machine let the planner's cycles run while it
  // followed the cueing: a sample a late planner tick took is written by
  // the bridge's tick on time, sooner after it (never below 0: every link
  // of the trace comes after the one before it). How long it takes is the
  // benchmark's figure.
  constexpr double kShortestChainMs = 0.4;
  const double planner_late_ms = static_cast<double>(LargestLateCycleUs(run.log_path, "EDSP_SETPOINT", 1000, 0, -1,
                                                                        first_cueing_utime, last_cueing_utime)) *
                                 1e-3;
  const double shortest_ms = std::max(0.0, kShortestChainMs - planner_late_ms);
  const nlohmann::json delay =
      CueingJson(run.dir, fmt::format("delay --log {} --sent {}/sent.csv", run.log_path, run.dir), "delay.json");
  // Nearly every sample a logged cueing setpoint came from: the stretch
  // this run's machine let the planner follow, less the setpoints a
  // stalled logger missed (a few more go with the commands and leg states
  // it missed).
  const int sent_while_followed = SentFollowed(run.dir + "/sent.csv", followed_segments);
  EXPECT_GT(sent_while_followed, delay["samples_sent"].get<double>() / 2) << "followed through the 10 s brake of 16";
  EXPECT_GE(delay["samples_traced"].get<double>(), 0.9 * sent_while_followed) << delay.dump();
  EXPECT_GE(delay["delay_min_ms"].get<double>(), shortest_ms)
      << delay.dump() << "; the planner's cycles up to " << planner_late_ms << " ms late";
  std::printf("vehicle sample -> drive write: %s; %d sent while the planner followed\n", delay.dump().c_str(),
              sent_while_followed);

  // The packets the cueing took went on the bus too (EDSP_VEHICLE, of its
  // session, stamped when they came), so the logger has the vehicle of a
  // run fed over UDP, and it is scored as one fed on the bus: every packet
  // sent is there, none refused, over a window of the lead at rest, the
  // brake and the tail after the disengage word.
  const nlohmann::json score = ExpectScoredAsTheBrakeOffline(run);
  EXPECT_GT(score["vehicle_samples"].get<double>(), 0.95 * delay["samples_sent"].get<double>()) << score.dump();
  EXPECT_EQ(score["vehicle_samples_refused"], 0) << "the cueing puts out only what it took: " << score.dump();
  std::printf("the UDP run scored: %s\n", score.dump().c_str());
}

TEST(CueingGroup, ASilentHostOnTheBusIsWashedHomeStillEngagedAnEStopWordHoldsItAndAnotherSessionsSamplesMoveNothing) {
  const PlatformModel model(Huang2021Config());
  const Vector6 home = model.home_pose().ToVector();
  SimGroupExtras group = CueingGroup();
  group.edit = [](GroupFileEditor& file) {
    file.SetArg("cueing", "--cueing", SourcePath("config/cueing.toml")).SetArg("cueing", "--input", "lcm");
  };
  const std::string to_bus = fmt::format("--to lcm --lcm-url '{}' --session-id auto", kGroupLcmUrl);
  std::int64_t foreign_sent_utime = 0;
  const GroupRun run = LaunchSimGroup(
      "cueing-silent", "signed", kCueingPlanner,
      [&](const std::string& dir) {
        std::ofstream(dir + "/rest.toml")
            << "name = \"rest\"\ndescription = \"a rider at rest\"\nduration_s = 0.1\n"
               "[[pulse]]\nchannel = \"fx\"\nrise_s = 0.01\nfall_s = 0.01\namplitude = 0.0\n";
        WaitForTheGroup();
        // Another session's host (a log replayed into this group) asks to engage for a second.
        EXPECT_EQ(Send(dir + "/rest.toml", "engage", 0.5, 0.5, "",
                       fmt::format("--to lcm --lcm-url '{}' --session-id {}", kGroupLcmUrl, kSession + 1)),
                  0);
        foreign_sent_utime = UtimeNow();
        // The brake, then silence mid-washout: the input fades to rest.
        EXPECT_EQ(Send(SourcePath("config/manoeuvres/braking.toml"), "silence", 3.0, 12.0, "", to_bus), 0);
        // A host back with e-stop: the planner holds, and ends the run.
        EXPECT_EQ(Send(dir + "/rest.toml", "estop", 0.0, 1.0, "", to_bus), 0);
      },
      kSession, kDefaultConfig, kStallTolerantStaleMs, group);
  ASSERT_EQ(run.exit_code, 0);
  const std::string faults = FaultLines(run.log_path);
  EXPECT_NE(faults.find(fmt::format("vehicle message of session {} refused", kSession + 1)), std::string::npos)
      << faults;
  const auto statuses = LoggedMessages<motion_status_t>(run.log_path, "EDSP_MOTION_STATUS");
  ASSERT_FALSE(statuses.empty());
  int before_the_host = 0;  // statuses while only the other session's host had sent
  for (const motion_status_t& s : statuses) {
    if (s.utime > foreign_sent_utime) break;
    ++before_the_host;
    EXPECT_NE(s.state, motion_status_t::STATE_CUEING) << "engaged by another session's samples at " << s.utime;
  }
  EXPECT_GT(before_the_host, 25) << "the planner's status at 50 Hz through the other host's second";
  EXPECT_EQ(statuses.back().last_end, motion_status_t::END_STOPPED) << statuses.back().reason;
  // Still cueing when the host came back: the washout had brought the rig home.
  std::int64_t ended_utime = 0;
  for (const motion_status_t& s : statuses) {
    if (ended_utime == 0 && s.state != motion_status_t::STATE_CUEING && s.request_id != 0 &&
        s.last_end == motion_status_t::END_STOPPED) {
      ended_utime = s.utime;
    }
  }
  ASSERT_NE(ended_utime, 0);
  const auto truths = LoggedMessages<rig_truth_t>(run.log_path, "EDSP_RIG_TRUTH");
  const rig_truth_t* at_stop = nullptr;
  for (const rig_truth_t& t : truths) {
    if (t.utime <= ended_utime) at_stop = &t;
  }
  ASSERT_NE(at_stop, nullptr);
  EXPECT_LT((TruthPose(*at_stop) - home).head<3>().norm(), 0.5e-3) << "washed home before the e-stop";

  // The run scored from its log: the vehicle as the group heard it, this
  // session's only, while the planner followed the cueing: the lead at
  // rest, then the brake, until the host fell silent.
  const nlohmann::json score = ExpectScoredAsTheBrakeOffline(run);
  std::printf("the live run scored: %s\n", score.dump().c_str());
}

}  // namespace
}  // namespace edsp
