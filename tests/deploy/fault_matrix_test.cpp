// Every node of a moving sim group frozen (SIGSTOP for 0.5 s, then SIGCONT)
// and killed (SIGKILL; the launcher restarts it), and over Modbus TCP the
// drive simulator killed and one of its drives faulted, one fault per run (label
// multiprocess, private network namespace). For each: the platform never
// jumps and is at rest within the hold time, the fault is on EDSP_FAULT (the
// launcher names the member; the bridge or the drives say what they did) and
// EDSP_STATUS, nothing logged is lost, and after the operator's re-arm the
// group follows the trajectory again and lands on its last pose within 5 µm.
// Each run prints a row of the README's robustness table (FAULT_ROW).
//
// The planner kill is not in it: the planner is the job (restart = "never";
// a restarted trajectory would start again from its beginning), and its
// freeze covers a silent setpoint stream.
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/fault_t.hpp"
#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_summary.h"
#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "edsp/transport/seq_gap.h"
#include "group_watch.h"
#include "late_cycles.h"
#include "sim_group_harness.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

constexpr std::int64_t kLauncherStepUs = 10000;  // edsp-launch watches its members every 10 ms

// SIGSTOP for 0.5 s then SIGCONT; SIGKILL (the launcher restarts it); or
// SIGUSR1 to edsp-drive-sim, which faults its drive 1 (error code FF01h)
// as a drive's own fault would, the process running on.
enum class Action { kFreeze, kKill, kDriveFault };

struct FaultCase {
  std::string member;   // group member name
  std::string program;  // its executable
  Action action;
  std::string output;  // an LCM channel only it publishes: its successor is back ("" = none)
  // "": the sim group; "sim-modbus" or "sim-cia402": the bridge a CiA 402
  // master of edsp-drive-sim, over Modbus TCP or the shared-memory image.
  std::string drives_group{};
  bool over_drive_sim() const { return !drives_group.empty(); }
};

std::string CaseName(const FaultCase& c) {
  return c.member + (c.action == Action::kKill ? "_killed" : c.action == Action::kFreeze ? "_frozen" : "_drive_fault");
}
void PrintTo(const FaultCase& c, std::ostream* os) { *os << CaseName(c); }

// Up 60 mm in z at 0.03 m/s, a 3.5 s hold at the top, back down, a final
// hold: the faults land mid-way up (moving), the rejoin has a hold to catch.
std::string TrajectoryCsv(const std::string& path) {
  std::ofstream(path) << "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n"
                      << "0,0,0,1.511,0,0,0\n0.5,0,0,1.511,0,0,0\n2.5,0,0,1.571,0,0,0\n"
                      << "6,0,0,1.571,0,0,0\n8,0,0,1.511,0,0,0\n9,0,0,1.511,0,0,0\n";
  return path;
}

// What the test did, on the nodes' clock (UtimeNow: CLOCK_REALTIME).
struct Timeline {
  std::int64_t fault_utime = 0;
  std::int64_t end_utime = 0;           // SIGCONT sent, or the killed member restarted
  std::int64_t arm_utime = 0;           // edsp-ctl arm sent (0: not needed)
  bool at_rest_before_arm = false;      // the watch saw the platform still before it
  std::int64_t taken_effect_utime = 0;  // the member stopped or dead, as the kernel has it
  int arm_status = -1;
  int extra_arms = 0;                 // re-arms after a later latch of a stalled bridge
  std::int64_t rearm_from_utime = 0;  // from when later latches were re-armed
  bool successor_seen = false;        // a killed member's successor published
  std::int64_t watch_lag_us = 0;      // how late the test saw the setpoint it struck on
};

// The member's pid as its launcher reported it on starting it (the latest
// start: a member restarted before the fault is its successor), found
// before the fault so that its time is the signal's. Read from the
// launcher's report, not searched for: a process started to search (pgrep)
// can take seconds to run on a loaded machine, or find nothing.
pid_t MemberPid(const FaultCase& c, const std::string& dir) {
  std::ifstream report(dir + "/launch.err");
  const std::regex started("^edsp-launch: (\\S+) +started +pid ([0-9]+)");
  long pid = -1;
  std::string line;
  std::smatch m;
  while (std::getline(report, line)) {
    if (std::regex_search(line, m, started) && m[1] == c.member) pid = std::stol(m[2]);
  }
  return static_cast<pid_t>(pid);
}

// The state letter of /proc/<pid>/stat ('R', 'S', 'T' stopped, 'Z'
// zombie), or 'X' once the process is gone.
char ProcessState(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return 'X';
  const std::size_t paren = text.rfind(')');
  return paren != std::string::npos && paren + 2 < text.size() ? text[paren + 2] : 'X';
}

// When the signal had taken effect in the kernel: the member stopped, or
// dead (a zombie or gone; a killed process's teardown can take hundreds of
// ms on a loaded machine, and only then can its launcher see it).
std::int64_t TakenEffectUtime(pid_t pid, bool kill) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < give_up) {
    const char state = ProcessState(pid);
    if (kill ? (state == 'Z' || state == 'X') : state == 'T') break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return UtimeNow();
}

int Arm(const std::string& dir) {
  int status = -1;
  // Retried as an operator would: a multicast burst on this VM can drop one.
  for (int attempt = 0; attempt < 3 && status != 0; ++attempt) {
    status =
        std::system(fmt::format("{} arm --operator fault-matrix --timeout-s 30 --group {}/group.toml >>{}/ctl.out 2>&1",
                                BuiltProgram("edsp-ctl"), dir, dir)
                        .c_str());
  }
  return status;
}

struct Truth {
  std::int64_t utime;
  std::int64_t seq;
  Vector3 p;
};

struct Analysis {
  std::vector<Truth> truth;
  std::optional<std::int64_t> first_report_utime;  // any EDSP_FAULT at or after the fault
  std::string first_report;
  std::optional<std::int64_t> launcher_report_utime;
  std::optional<std::int64_t> rejoined_utime;     // bridge: following the stream again
  std::optional<std::int64_t> armed_utime;        // bridge: re-armed
  std::optional<std::int64_t> restarted_utime;    // launcher: member restarted
  std::optional<std::int64_t> hold_report_utime;  // bridge or drives: holding
  std::string hold_report;
  std::string bridge_reports;          // what the bridge said from the fault on, a line each
  std::int64_t resumed_utime = 0;      // the first event after the log's gap
  bool bridge_status_holding = false;  // EDSP_STATUS after the fault
  bool launcher_status_fault = false;
  std::int64_t launcher_step_max_us =
      -1;                             // its watch steps' longest interval, in its first EDSP_STATUS from its report on
  std::int64_t launcher_late_us = 0;  // that past its 10 ms
  std::int64_t logger_drops = 0;      // what the logger said it lost (EDSP_STATUS)
  // The launcher's own messages missing from the log: its EDSP_STATUS seq
  // gaps, and faults it counted out (messages_out) that the log lacks (from
  // its first status the log has: the logger starts after it).
  std::int64_t launcher_lost = 0;
  std::int64_t first_event_utime = 0;
  std::int64_t events_before_fault = 0;
  std::int64_t largest_event_gap_us = 0;            // between logged events after the fault
  std::int64_t tracker_gaps = 0, command_gaps = 0;  // seq gaps in the log
  // The tracker's seq gaps within the fault's window (from the fault to
  // kDrainUs after its end: a thawed logger drains its socket) and outside
  // it (a logger that cannot keep up with the group drops some all along),
  // and the span of the tracker's samples in the log.
  std::int64_t tracker_gaps_in_window = 0, tracker_gaps_outside = 0;
  std::int64_t first_tracker_utime = 0, last_tracker_utime = 0;
  std::string logger_resumed;
  bool damaged = false;
  tracker_point_t last_tracker{};
  pose_setpoint_t last_setpoint{};
};

constexpr std::int64_t kDrainUs = 500000;
bool InFaultWindow(const Timeline& t, std::int64_t utime) {
  return utime >= t.fault_utime && utime <= t.end_utime + kDrainUs;
}

// The tracker samples a logger that drops some all along (sanitized, on a
// machine half as fast) would have dropped within the fault's window anyway,
// at the rate it dropped them outside it.
std::int64_t OrdinaryLossInWindow(const Analysis& a, const Timeline& t) {
  const std::int64_t window_us = t.end_utime + kDrainUs - t.fault_utime;
  const std::int64_t outside_us = a.last_tracker_utime - a.first_tracker_utime - window_us;
  if (outside_us <= 0) return 0;
  return a.tracker_gaps_outside * window_us / outside_us;
}

Analysis Analyse(const std::string& log_path, const Timeline& t) {
  Analysis a;
  LogReader reader(log_path);
  LogEvent e;
  std::int64_t previous_event_utime = 0, last_tracker_seq = -1, last_command_seq = -1;
  bool launcher_status_read = false;
  std::int64_t launcher_faults = 0, last_launcher_status_seq = -1;
  std::optional<std::int64_t> launcher_faults_unlogged;  // at its first status in the log
  while (reader.Next(&e)) {
    const int size = static_cast<int>(e.data.size());
    if (a.first_event_utime == 0) a.first_event_utime = e.timestamp_utime;
    if (e.timestamp_utime < t.fault_utime) ++a.events_before_fault;
    if (previous_event_utime > 0 && e.timestamp_utime > t.fault_utime &&
        e.timestamp_utime - previous_event_utime > a.largest_event_gap_us) {
      a.largest_event_gap_us = e.timestamp_utime - previous_event_utime;
      a.resumed_utime = e.timestamp_utime;
    }
    previous_event_utime = e.timestamp_utime;
    if (e.channel == "EDSP_RIG_TRUTH") {
      rig_truth_t m;
      if (m.decode(e.data.data(), 0, size) >= 0)
        a.truth.push_back({m.utime, m.seq, Vector3(m.pose[0], m.pose[1], m.pose[2])});
    } else if (e.channel == "EDSP_TRACKER") {
      tracker_point_t m;
      if (m.decode(e.data.data(), 0, size) < 0) continue;
      const std::int64_t gap = SeqGap(last_tracker_seq, m.seq);
      a.tracker_gaps += gap;
      (InFaultWindow(t, m.utime) ? a.tracker_gaps_in_window : a.tracker_gaps_outside) += gap;
      if (a.first_tracker_utime == 0) a.first_tracker_utime = m.utime;
      a.last_tracker_utime = m.utime;
      last_tracker_seq = m.seq;
      a.last_tracker = m;
    } else if (e.channel == "EDSP_LEG_COMMAND") {
      std::vector<std::uint8_t> head(e.data.begin(), e.data.begin() + std::min<std::size_t>(24, e.data.size()));
      EdspHeader h;
      if (!ParseEdspHeader(head, &h)) continue;
      a.command_gaps += SeqGap(last_command_seq, h.seq);
      last_command_seq = h.seq;  // a restarted kinematics starts again at 1: no gap
    } else if (e.channel == "EDSP_SETPOINT") {
      pose_setpoint_t m;
      if (m.decode(e.data.data(), 0, size) >= 0) a.last_setpoint = m;
    } else if (e.channel == "EDSP_REPLY") {
      // The first re-arm (an unanswered one is retried).
      reply_t r;
      if (r.decode(e.data.data(), 0, size) >= 0 && r.node == "actuator_bridge" && r.code == reply_t::CODE_DONE &&
          !a.armed_utime) {
        a.armed_utime = r.utime;
      }
    } else if (e.channel == "EDSP_FAULT") {
      fault_t f;
      if (f.decode(e.data.data(), 0, size) < 0) continue;
      if (f.utime >= t.fault_utime && !a.first_report_utime && f.severity >= fault_t::SEVERITY_WARNING) {
        a.first_report_utime = f.utime;
        a.first_report = f.node + ": " + f.reason;
      }
      if (f.node == "launcher") ++launcher_faults;
      if (f.node == "launcher" && f.utime >= t.fault_utime && !a.launcher_report_utime)
        a.launcher_report_utime = f.utime;
      if (f.node == "launcher" && f.reason.find("restarted as pid") != std::string::npos) a.restarted_utime = f.utime;
      // The rejoin after the first re-arm (its confirmation, or its request:
      // a confirmation the logger lost).
      if (f.node == "actuator_bridge" && f.reason.find("rejoined the command stream") != std::string::npos &&
          (a.armed_utime || (t.arm_utime > 0 && f.utime >= t.arm_utime)) && !a.rejoined_utime) {
        a.rejoined_utime = f.utime;
      }
      if (f.utime >= t.fault_utime && !a.hold_report_utime && f.severity >= fault_t::SEVERITY_WARNING &&
          (f.node == "actuator_bridge" || f.node == "rig")) {
        a.hold_report_utime = f.utime;
        a.hold_report = f.node + ": " + f.reason;
      }
      // By when the log received it, not its stamp: a bridge cycle that
      // began before the fault may read the drive it faulted and report it
      // with its own start's stamp (the later the machine runs, the more
      // often); what was received after the fault was sent after it.
      if (f.node == "actuator_bridge" && e.timestamp_utime >= t.fault_utime) a.bridge_reports += f.reason + "\n";
      if (f.node == "logger" && f.reason.find("resumed after") != std::string::npos) a.logger_resumed = f.reason;
    } else if (e.channel == "EDSP_STATUS") {
      node_status_t s;
      if (s.decode(e.data.data(), 0, size) < 0) continue;
      if (s.node == "launcher") {
        if (last_launcher_status_seq >= 0)
          a.launcher_lost += std::max<std::int64_t>(0, s.seq - last_launcher_status_seq - 1);
        last_launcher_status_seq = s.seq;
        if (!launcher_faults_unlogged) launcher_faults_unlogged = s.messages_out - launcher_faults;
        a.launcher_lost = std::max(a.launcher_lost, s.messages_out - launcher_faults - *launcher_faults_unlogged);
      }
      if (s.node == "actuator_bridge" && e.timestamp_utime >= t.fault_utime && s.state == node_status_t::STATE_HOLDING)
        a.bridge_status_holding = true;  // received after the fault, as its reports
      if (s.utime < t.fault_utime) continue;
      if (s.node == "launcher" && s.state == node_status_t::STATE_FAULT) a.launcher_status_fault = true;
      if (s.node == "launcher" && a.launcher_report_utime && s.utime >= *a.launcher_report_utime &&
          !launcher_status_read) {
        a.launcher_step_max_us = std::llround(s.loop_max_us);
        a.launcher_late_us = std::max<std::int64_t>(0, a.launcher_step_max_us - kLauncherStepUs);
        launcher_status_read = true;
      }
      if (s.node == "logger") a.logger_drops = std::max(a.logger_drops, s.drops);
    }
  }
  a.damaged = reader.damaged();
  return a;
}

// The platform at rest from when on, before `until` (the re-arm): the first
// true sample after which it stays within 1 µm of where it ends up.
std::optional<std::int64_t> AtRestFrom(const std::vector<Truth>& truth, std::int64_t from, std::int64_t until) {
  std::vector<Truth> window;
  for (const Truth& s : truth) {
    if (s.utime >= from && s.utime < until) window.push_back(s);
  }
  if (window.size() < 50) return std::nullopt;
  const Vector3 rest = window.back().p;
  std::size_t k = window.size();
  while (k > 0 && (window[k - 1].p - rest).norm() <= 1e-6) --k;
  return window[k == window.size() ? k - 1 : k].utime;
}

// The largest step of the platform between true samples 1 ms apart
// (samples further apart are a gap in the log or a late cycle, not motion
// within one cycle), and the largest across a restart of the rig (its seq
// starts again: the successor resumes where the platform stopped).
double LargestCycleStep(const std::vector<Truth>& truth) {
  double largest = 0.0;
  for (std::size_t k = 1; k < truth.size(); ++k) {
    if (truth[k].utime - truth[k - 1].utime > 5000) continue;
    largest = std::max(largest, (truth[k].p - truth[k - 1].p).norm());
  }
  return largest;
}
double LargestRestartStep(const std::vector<Truth>& truth) {
  double largest = 0.0;
  for (std::size_t k = 1; k < truth.size(); ++k) {
    if (truth[k].seq > truth[k - 1].seq) continue;
    largest = std::max(largest, (truth[k].p - truth[k - 1].p).norm());
  }
  return largest;
}

// The first true sample at or after `utime` (the restarted rig's first).
std::int64_t FirstTruthFrom(const std::vector<Truth>& truth, std::int64_t utime) {
  for (const Truth& s : truth) {
    if (s.utime >= utime) return s.utime;
  }
  return utime;
}

// When the signal took effect: the member's last message on its 1 kHz
// output before the silence (> 20 ms) that ends after the test sent it. On
// a busy machine the sending thread can be descheduled for hundreds of ms
// between taking the time and the kill, and a starved member's stamps can
// trail the signal by tens of ms (a rig catching up stamps each cycle at
// its own instant); every latency is timed from here.
std::int64_t SilencedFrom(const std::string& log_path, const std::string& channel, std::int64_t sent_utime) {
  LogReader reader(log_path);
  LogEvent e;
  EdspHeader previous, header;
  bool have_previous = false;
  while (reader.Next(&e)) {
    if (e.channel != channel || !ParseEdspHeader(e.data, &header)) continue;
    if (have_previous && header.utime > sent_utime && header.utime - previous.utime > 20000) {
      // A cycle's stamp can lead the moment it was sent by up to a period
      // (a 1 ms loop stamps its deadline): the member was still running 1 ms
      // before its last stamp, and whatever reacted to its stop came later.
      return std::max(sent_utime, previous.utime - 1000);
    }
    previous = header;
    have_previous = true;
  }
  return sent_utime;
}

// The successor's first true sample after a restart of the rig (its seq
// starts again), or `utime` if none.
std::int64_t FirstRestartedTruth(const std::vector<Truth>& truth, std::int64_t utime) {
  for (std::size_t k = 1; k < truth.size(); ++k) {
    if (truth[k].utime >= utime && truth[k].seq < truth[k - 1].seq) return truth[k].utime;
  }
  return utime;
}

// Events of one 1 kHz channel logged before `utime` against what its
// publisher sent meanwhile (seq span): what the log still holds of the time
// before a fault, whatever the machine's start-up took.
struct SamplesBefore {
  std::int64_t published = 0, logged = 0;
  double fraction() const { return published > 0 ? static_cast<double>(logged) / static_cast<double>(published) : 0.0; }
};
SamplesBefore CountSamplesBefore(const std::vector<Truth>& truth, std::int64_t utime) {
  SamplesBefore n;
  std::int64_t first_seq = -1;
  for (const Truth& s : truth) {
    if (s.utime >= utime) break;
    if (first_seq < 0) first_seq = s.seq;
    n.published = s.seq - first_seq + 1;
    ++n.logged;
  }
  return n;
}

// Messages missing from the log by their seq, on the 1 kHz channels the
// logger takes from LCM (the leg commands come from a ring here, whose
// overruns say nothing of LCM datagrams).
std::int64_t LostFromTheLog(const std::string& log_path) {
  const LogSummary summary = SummarizeLog(log_path);
  std::int64_t lost = 0;
  for (const char* channel : {"EDSP_SETPOINT", "EDSP_LEG_STATE", "EDSP_RIG_TRUTH", "EDSP_TRACKER"}) {
    const auto it = summary.channels.find(channel);
    if (it != summary.channels.end()) lost += it->second.seq_gaps;
  }
  return lost;
}

class FaultMatrix : public ::testing::TestWithParam<FaultCase> {};

TEST_P(FaultMatrix, HoldsWithoutAJumpReportsAndRecoversAfterReArm) {
  const FaultCase c = GetParam();
  const bool kill = c.action == Action::kKill, drive_fault = c.action == Action::kDriveFault;
  const std::string name = "matrix_" + CaseName(c);
  const std::string dir = test_support::SimGroupDir(name);
  std::system(("mkdir -p " + dir).c_str());
  const std::string csv = TrajectoryCsv(dir + "/trajectory.csv");
  const bool motion_stops = c.member != "logger";
  Timeline t;
  SimGroupExtras extras;
  std::string config = test_support::kDefaultConfig;
  if (c.over_drive_sim()) {
    // The drives' fieldbus timeout and the master's response timeout at the
    // stale limit: the bridge's and drives' watchdogs over the link.
    extras = test_support::OverModbus(dir, test_support::kShippedStaleMs, &config, c.drives_group);
    ASSERT_FALSE(config.empty()) << "config/huang2021.toml declares no [drives] counts_per_m";
  }
  // The leg commands on shared memory: a killed kinematics leaves its
  // segment behind, and its successor must take it over (stale segment).
  extras.edit = [drives = extras.edit](GroupFileEditor& g) {
    if (drives) drives(g);
    g.SetChannel("EDSP_LEG_COMMAND", "path", "both");
  };
  const GroupRun run = LaunchSimGroup(
      name, "signed", fmt::format(R"("--csv", "{}", "--exit-after-hold-s", "0.5")", csv),
      [&](const std::string& d) {
        test_support::GroupWatch watch(test_support::kGroupLcmUrl, c.output.empty() ? "" : c.output);
        // A third of the way up (20 of 60 mm), however long the group took to start.
        if (!watch.WaitForSetpoint([](const pose_setpoint_t& s) { return s.pose[2] > 1.531; },
                                   std::chrono::seconds(60))) {
          return;  // fails below: no fault time
        }
        t.watch_lag_us = watch.SetpointLagUs();
        const pid_t pid = MemberPid(c, d);
        if (pid <= 0) return;
        const int restarts = c.output.empty() ? 0 : watch.Restarts(c.output);
        t.fault_utime = UtimeNow();
        ::kill(pid, kill ? SIGKILL : drive_fault ? SIGUSR1 : SIGSTOP);
        t.taken_effect_utime = drive_fault ? t.fault_utime : TakenEffectUtime(pid, kill);
        if (drive_fault) {
          t.end_utime = t.fault_utime;  // the process runs on; the drive stays faulted until re-armed
        } else if (kill) {
          // The launcher restarts it: its successor publishes (its seq
          // starts again), however long a cold or sanitized start takes.
          if (c.over_drive_sim()) {
            // The bridge reads the successor's drives (out of operation until re-armed).
            t.successor_seen = watch.WaitForFault("actuator_bridge", "drive 1 in switch on disabled", t.fault_utime,
                                                  std::chrono::seconds(30));
          } else if (c.output.empty()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(800));
            t.successor_seen = true;
          } else {
            t.successor_seen = watch.WaitForRestart(c.output, restarts, std::chrono::seconds(30));
          }
        } else {
          std::this_thread::sleep_for(std::chrono::milliseconds(500));
          ::kill(pid, SIGCONT);
          t.end_utime = UtimeNow();
        }
        if (motion_stops) {
          // Re-armed once the hold has settled (the platform still for
          // 300 ms from here on), however long a loaded machine takes to
          // bring it to rest; an arm before it would cut the hold measured
          // below (which then fails on it).
          t.at_rest_before_arm =
              watch.WaitForRest(UtimeNow(), std::chrono::milliseconds(300), std::chrono::seconds(30));
          t.arm_utime = UtimeNow();
          t.arm_status = Arm(d);
        }
        // A fault that stops nothing (the logger's) is no reason for a
        // latch, but a machine stall later in the run may be: re-armed in
        // every case, and each such latch must be explained by a stall.
        t.rearm_from_utime = UtimeNow();
        t.extra_arms = test_support::ReArmWhileLatched(&watch, [&] { Arm(d); });
      },
      77, config, test_support::kShippedStaleMs, extras);
  std::ifstream launch_err(dir + "/launch.err");
  std::ostringstream launch_text;
  launch_text << launch_err.rdbuf();
  ASSERT_EQ(run.exit_code, 0) << launch_text.str();
  ASSERT_GT(t.fault_utime, 0) << "no " << c.program << " process of this group found";
  // The fault is meant mid-way up: from 20 of the 60 mm up, 1.3 s of the
  // climb are left. A watch further behind the group than that struck in
  // the hold at the top, where a restarted bridge rightly follows a stream
  // that stands where its drives do: nothing below would test the case.
  EXPECT_LT(t.watch_lag_us, 1'000'000) << "the test saw the platform " << t.watch_lag_us / 1000
                                       << " ms late: the fault did not land while it climbed";
  const std::int64_t sent_utime = t.fault_utime;
  if (!c.output.empty()) t.fault_utime = SilencedFrom(run.log_path, c.output, sent_utime);
  const Analysis a = Analyse(run.log_path, t);
  const bool logger_killed = c.member == "logger" && kill;
  if (kill) {
    EXPECT_TRUE(t.successor_seen) << "no successor of " << c.member << " published within 30 s";
  }
  if (kill && !logger_killed) {
    ASSERT_TRUE(a.restarted_utime.has_value()) << "the launcher never restarted " << c.member << "\n"
                                               << launch_text.str();
    t.end_utime = *a.restarted_utime;
  }
  if (logger_killed) t.end_utime = a.resumed_utime;  // its successor's first event

  // Nothing logged is lost: the log reads to its end, starts before the
  // fault (a restarted logger appends, never truncates) and holds what the
  // rig published before it, however long the group took to start.
  EXPECT_FALSE(a.damaged);
  EXPECT_GT(a.first_event_utime, 0);
  EXPECT_LT(a.first_event_utime, t.fault_utime - 500000) << "the log starts at the fault: truncated?";
  // Most of it: loopback multicast on a busy machine loses a few per cent,
  // a sanitized logger at half speed a tenth; either way counted on the
  // logger's EDSP_STATUS. A log missing its head or a chunk of it holds far
  // less, and its logger never said it lost them.
  const SamplesBefore before = CountSamplesBefore(a.truth, t.fault_utime);
  const std::int64_t missing = before.published - before.logged;
  EXPECT_GT(before.fraction(), 0.5);
  EXPECT_TRUE(before.fraction() > 0.9 || missing <= a.logger_drops)
      << "the log holds " << before.fraction() * 100.0 << "% of the rig's samples before the fault; " << missing
      << " missing, of which the logger reported " << a.logger_drops << " lost";
  // The machine's own lateness in this run, around the fault: a busy or
  // sanitized machine delays every node's reaction by as much; a hold or
  // report that never comes still fails.
  // Every 1 kHz loop that ran on through the fault (the faulted member's
  // own silence left out), within 2 s of it.
  const std::int64_t fault_over = std::max(t.end_utime, t.fault_utime);
  std::int64_t late_us = 0;
  for (const char* channel : {"EDSP_RIG_TRUTH", "EDSP_LEG_STATE", "EDSP_SETPOINT"}) {
    // Over Modbus the bridge's own cycle blocks in the exchange with the
    // faulted simulator (a response timeout, a reconnect): its lateness
    // then is the fault's, not the machine's, and loosens no limit.
    const bool own = c.output == channel || (c.over_drive_sim() && std::string(channel) == "EDSP_LEG_STATE");
    late_us = std::max(late_us, test_support::LargestLateCycleUs(run.log_path, channel, 1000, own ? t.fault_utime : 0,
                                                                 own ? fault_over + 100000 : -1,
                                                                 t.fault_utime - 2000000, fault_over + 2000000));
  }
  const double late_ms = static_cast<double>(late_us) * 1e-3;
  if (t.extra_arms > 0) {
    // A later latch is the machine's, not the bridge's: a loop feeding the
    // bridge (or the bridge itself) ran late by half its stale limit or
    // more, or the rig emulator's drives fell silent by half their timeout
    // (late_cycles.h). Looked for from shortly before the latch the test
    // re-armed (a fault that stops nothing, the logger's, is not re-armed
    // at all: from the fault on).
    const std::int64_t stale_us = std::int64_t{test_support::kShippedStaleMs} * 1000;
    const std::int64_t latches_from = (motion_stops ? t.arm_utime : t.fault_utime) - 2 * stale_us;
    const test_support::LatenessAroundTheBridge later =
        test_support::LatenessAroundTheBridgeWithin(run.log_path, latches_from);
    EXPECT_TRUE(later.ExplainsALatch(stale_us))
        << "the bridge latched " << t.extra_arms
        << " more time(s) after the re-arm with no stall to explain it: " << later.Describe();
  }
  // Reported: by the launcher naming the member, within 50 ms. The logger
  // cannot be relied on to record its own fault (killed: nobody records;
  // frozen: what arrives meanwhile may overflow when it thaws), so for it
  // the launcher's stderr is the evidence.
  if (c.member == "logger") {
    const std::string said = kill ? "logger           exited   (signal 9)" : "logger           frozen";
    EXPECT_NE(launch_text.str().find(said), std::string::npos) << launch_text.str();
  } else if (drive_fault) {
    // The member runs on: nothing for the launcher to say. The bridge is
    // the first to (checked below: which drive, its error code).
    EXPECT_FALSE(a.launcher_report_utime.has_value()) << "the launcher reported a member that ran on";
  } else if (const std::int64_t lost = std::max(a.logger_drops, LostFromTheLog(run.log_path));
             (!a.launcher_report_utime && lost > 0) || a.launcher_lost > 0) {
    // The logger lost datagrams (a sanitized logger on a loaded machine):
    // counted on its EDSP_STATUS, seen as gaps in the seq of what it took
    // from LCM (losses after its last status), or missing from the
    // launcher's own (a later report of its, the restart, is then no
    // measure of the first). The launcher's fault may be among them, so its
    // stderr is the evidence that it reported; its timing is not
    // measurable then.
    const std::string said = fmt::format("edsp-launch: {:<16} {}", c.member, kill ? "exited" : "frozen");
    const std::string text = launch_text.str();
    EXPECT_NE(text.find(said), std::string::npos)
        << "no launcher report for " << c.member << " in the log (the logger lost " << lost
        << " datagrams, the launcher's own " << a.launcher_lost << ") nor on its stderr:\n"
        << text;
  } else {
    ASSERT_TRUE(a.launcher_report_utime.has_value()) << "no launcher fault for " << c.member;
    // From when the kernel had stopped or reaped-to-zombie the member: the
    // launcher cannot see it earlier.
    // Late by the group's 1 kHz loops, or by the launcher's own watch steps
    // (its first status from its report on): the sanitized nodes on a slow
    // machine starve the launcher longer than their own loops run late.
    EXPECT_LT(*a.launcher_report_utime - std::max(t.fault_utime, t.taken_effect_utime),
              50000 + std::max(late_us, a.launcher_late_us))
        << "the launcher's steps ran late by " << a.launcher_late_us / 1000 << " ms at most";
    // Its status measures its steps (none measured would excuse nothing).
    EXPECT_GE(a.launcher_step_max_us, kLauncherStepUs) << "no launcher EDSP_STATUS with its step intervals";
    EXPECT_TRUE(a.launcher_status_fault) << "the launcher's EDSP_STATUS never said fault";
  }
  if (c.over_drive_sim()) {
    // Over the link the bridge says which link failed and why, then, once
    // it reads the drives again, which drive is out of operation and why
    // (the frozen simulator's drives: their fieldbus timeout, 8130h). A
    // drive's own fault leaves the link up: the drive and its code.
    if (!drive_fault) {
      const std::string link = c.drives_group == "sim-modbus" ? "modbus-tcp 127.0.0.1:1502" : "cia402-shm edsp.test.";
      EXPECT_NE(a.bridge_reports.find(link), std::string::npos) << a.bridge_reports;
    }
    std::printf("the bridge said, from the fault on:\n%s", a.bridge_reports.c_str());
    const char* why = kill          ? "drive 1 in switch on disabled"
                      : drive_fault ? "drive 1 in fault (error code FF01h)"
                                    : "error code 8130h";
    EXPECT_NE(a.bridge_reports.find(why), std::string::npos) << a.bridge_reports;
  }
  const double report_ms =
      a.first_report_utime ? static_cast<double>(*a.first_report_utime - t.fault_utime) * 1e-3 : -1.0;

  // No jump: no step beyond a servo cycle's travel (0.03 m/s, or catching
  // up a late cycle: what the command advanced while the machine stalled,
  // up to the legs' 0.5 m/s), and none across a restarted rig (a jump home
  // is 20 mm; a thawed bridge's accepted stale command was 0.97 mm a cycle).
  const double step_limit_m = std::min(5e-4, 2e-4 + 0.03 * late_ms * 1e-3);
  const double largest_step = LargestCycleStep(a.truth);
  EXPECT_LT(largest_step, step_limit_m);
  EXPECT_LT(LargestRestartStep(a.truth), step_limit_m) << "the restarted rig did not resume where the platform was";

  double hold_ms = -1.0, overrun_um = 0.0, rejoin_ms = -1.0, hold_report_ms = -1.0;
  if (motion_stops) {
    // The bridge's confirmation in the log is the evidence of the re-arm;
    // edsp-ctl's own exit status is operator_commands_test's (a sanitized
    // edsp-ctl under this group's traffic has missed the answer within its
    // 2 s, though the bridge had re-armed). Unless the logger lost
    // datagrams (counted on its EDSP_STATUS): the confirmation may be among
    // them, and edsp-ctl's answer is then the evidence, at its request.
    std::optional<std::int64_t> armed_utime = a.armed_utime;
    if (!armed_utime && a.logger_drops > 0 && t.arm_status == 0) armed_utime = t.arm_utime;
    ASSERT_TRUE(armed_utime.has_value()) << "the bridge never confirmed the re-arm (edsp-ctl exit " << t.arm_status
                                         << "; the logger lost " << a.logger_drops << ")";
    ASSERT_TRUE(a.hold_report_utime.has_value()) << "neither the bridge nor the drives reported a hold from "
                                                 << t.fault_utime << " (signal sent at " << sent_utime << ") on";
    hold_report_ms = static_cast<double>(*a.hold_report_utime - t.fault_utime) * 1e-3;
    EXPECT_TRUE(t.at_rest_before_arm) << "the platform was not still for 300 ms within 30 s of the fault's end";
    // A frozen or killed rig is the world stopped: its platform cannot
    // move until it (or its successor) runs again, so its hold is timed
    // from its first cycle after the fault, not from its start-up time.
    const std::int64_t from = c.member != "rig" ? t.fault_utime
                              : kill            ? FirstRestartedTruth(a.truth, t.fault_utime)
                                                : FirstTruthFrom(a.truth, t.end_utime);
    const auto rest = AtRestFrom(a.truth, from, *armed_utime);
    ASSERT_TRUE(rest.has_value());
    hold_ms = static_cast<double>(*rest - from) * 1e-3;
    // At rest within the bridge's 50 ms stale limit plus the servo
    // settling, and the machine's lateness measured in this run.
    EXPECT_LT(hold_ms, 150.0 + late_ms);
    EXPECT_LT(hold_report_ms, 100.0 + late_ms);
    Vector3 at_fault = a.truth.front().p;
    for (const Truth& s : a.truth) {
      if (s.utime <= t.fault_utime)
        at_fault = s.p;
      else if (s.utime < *armed_utime)
        overrun_um = std::max(overrun_um, (s.p - at_fault).norm() * 1e6);
    }
    // The platform's lag behind the command at 0.03 m/s, and 50 ms of it
    // (and of the machine's lateness).
    EXPECT_LT(overrun_um, 3000.0 + 30.0 * late_ms) << "the platform went on past the fault";
    ASSERT_TRUE(a.rejoined_utime.has_value()) << "the bridge never rejoined the stream";
    rejoin_ms = static_cast<double>(*a.rejoined_utime - *armed_utime) * 1e-3;
    EXPECT_TRUE(a.bridge_status_holding) << "EDSP_STATUS never said holding";
  } else {
    // The logger: the platform never stopped; a freeze loses nothing (the
    // socket buffer holds 0.5 s), a kill loses its restart time and no more.
    // Only a later latch the test re-armed (each explained by a stall,
    // checked above) makes the bridge rejoin the stream.
    if (t.extra_arms == 0) {
      EXPECT_FALSE(a.rejoined_utime.has_value());
    }
    if (!kill) {
      // 0.5 s of the group's ~5 000 packets a second overflow the socket and
      // LCM's receive ring when the logger thaws: lost, but counted and
      // reported (EDSP_STATUS drops), never more than the freeze.
      // Within the freeze's window; a logger that cannot keep up (sanitized,
      // on a slow machine) drops some all along, so the window may lose as
      // many more as it lost outside it at the same rate.
      const std::int64_t frozen_ms = (t.end_utime - t.fault_utime + late_us) / 1000;
      const std::int64_t ordinary = OrdinaryLossInWindow(a, t);
      EXPECT_LT(a.tracker_gaps_in_window, frozen_ms + 100 + ordinary)
          << a.tracker_gaps_outside << " lost outside the window, as many as " << ordinary << " expected in it";
      EXPECT_GE(a.logger_drops, a.tracker_gaps) << "the logger must report what it lost";
    } else {
      // The successor says it appended (its note on EDSP_FAULT is one
      // datagram to itself, which a sanitized logger under load has lost;
      // its stderr is the launcher's record), and the log's head is there
      // (checked above).
      const bool said_in_log = a.logger_resumed.find("resumed after") != std::string::npos;
      const bool said_on_stderr = launch_text.str().find("edsp-logger: ") != std::string::npos &&
                                  launch_text.str().find("resumed after") != std::string::npos;
      EXPECT_TRUE(said_in_log || said_on_stderr) << "the restarted logger must append to the log, not truncate it";
      // Its restart time and no more: as long as this run's first start
      // took (launch to the first event, less the start delays before it).
      const std::int64_t first_start_us = a.first_event_utime - run.launch_utime;
      EXPECT_LT(a.largest_event_gap_us, 1000000 + first_start_us);
    }
  }

  // Recovered: the last pose of the trajectory, reached and measured.
  const PlatformModel model(Huang2021Config());
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = a.last_setpoint.pose[k];
  const Vector3 target = model.ObservationPoint(Pose::FromVector(q));
  const Vector3 measured(a.last_tracker.point_m[0], a.last_tracker.point_m[1], a.last_tracker.point_m[2]);
  const double final_um = (measured - target).norm() * 1e6;
  EXPECT_LT(final_um, 5.0);

  const double end_ms = static_cast<double>(t.end_utime - t.fault_utime) * 1e-3;
  const auto ms = [](double v) { return v >= 0 ? fmt::format("{:.1f}", v) : std::string("-"); };
  // | member | fault | first report | hold reported | at rest | overrun | fault over | re-arm → following | lost |
  // final |
  std::printf(
      "late cycles: %.1f ms at most around the fault; the member fell silent %.1f ms and was stopped/dead "
      "%.1f ms after the signal was sent; %d re-arm(s) after a later stall\n",
      late_ms, static_cast<double>(t.fault_utime - sent_utime) * 1e-3,
      static_cast<double>(t.taken_effect_utime - sent_utime) * 1e-3, t.extra_arms);
  std::printf("FAULT_ROW | %s | %s | %s | %s | %s | %s | %.0f | %s | %lld | %.2f | %s | %s\n", c.member.c_str(),
              kill          ? "SIGKILL + restart"
              : drive_fault ? "SIGUSR1: drive 1 fault FF01h"
                            : "SIGSTOP 0.5 s",
              ms(report_ms).c_str(), ms(hold_report_ms).c_str(), motion_stops ? ms(hold_ms).c_str() : "no hold",
              motion_stops ? fmt::format("{:.0f}", overrun_um).c_str() : "-", end_ms, ms(rejoin_ms).c_str(),
              static_cast<long long>(a.tracker_gaps), final_um, a.first_report.c_str(), a.hold_report.c_str());
  RecordProperty("report_ms", static_cast<int>(report_ms));
  RecordProperty("hold_ms", static_cast<int>(hold_ms));
  RecordProperty("rejoin_ms", static_cast<int>(rejoin_ms));
}

INSTANTIATE_TEST_SUITE_P(
    EveryNode, FaultMatrix,
    ::testing::Values(FaultCase{"planner", "edsp-planner", Action::kFreeze, "EDSP_SETPOINT"},
                      FaultCase{"kinematics", "edsp-kinematics", Action::kFreeze, "EDSP_LEG_COMMAND"},
                      FaultCase{"kinematics", "edsp-kinematics", Action::kKill, "EDSP_LEG_COMMAND"},
                      FaultCase{"actuator_bridge", "edsp-actuator-bridge", Action::kFreeze, "EDSP_LEG_STATE"},
                      FaultCase{"actuator_bridge", "edsp-actuator-bridge", Action::kKill, "EDSP_LEG_STATE"},
                      FaultCase{"rig", "edsp-rig", Action::kFreeze, "EDSP_RIG_TRUTH"},
                      FaultCase{"rig", "edsp-rig", Action::kKill, "EDSP_RIG_TRUTH"},
                      FaultCase{"logger", "edsp-logger", Action::kFreeze, ""},
                      FaultCase{"logger", "edsp-logger", Action::kKill, ""}),
    [](const ::testing::TestParamInfo<FaultCase>& param_info) { return CaseName(param_info.param); });

// The drives over Modbus TCP (the sim-modbus group): the drive simulator
// frozen (the master's response timeout, then the drives' own fieldbus
// timeout), killed (the connection reset, then refused until the
// launcher's restart serves drives out of operation), and one drive
// raising a fault of its own.
INSTANTIATE_TEST_SUITE_P(
    OverModbus, FaultMatrix,
    ::testing::Values(FaultCase{"drive_sim", "edsp-drive-sim", Action::kFreeze, "", "sim-modbus"},
                      FaultCase{"drive_sim", "edsp-drive-sim", Action::kKill, "", "sim-modbus"},
                      FaultCase{"drive_sim", "edsp-drive-sim", Action::kDriveFault, "", "sim-modbus"}),
    [](const ::testing::TestParamInfo<FaultCase>& param_info) { return CaseName(param_info.param); });

// The same three over the drives' CSP image in shared memory (the
// sim-cia402 group): frozen (the master sees no newly latched image for
// its response timeout, then the drives' own fieldbus timeout), killed
// (its side of the image gone, then a successor's drives out of
// operation until re-armed), a drive's own fault.
INSTANTIATE_TEST_SUITE_P(
    OverSharedMemory, FaultMatrix,
    ::testing::Values(FaultCase{"drive_sim", "edsp-drive-sim", Action::kFreeze, "", "sim-cia402"},
                      FaultCase{"drive_sim", "edsp-drive-sim", Action::kKill, "", "sim-cia402"},
                      FaultCase{"drive_sim", "edsp-drive-sim", Action::kDriveFault, "", "sim-cia402"}),
    [](const ::testing::TestParamInfo<FaultCase>& param_info) { return CaseName(param_info.param); });

}  // namespace
}  // namespace edsp
