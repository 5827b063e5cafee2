#include "sim_group_harness.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_summary.h"
#include "edsp/fault_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "edsp/node_status_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp::test_support {

std::string SimGroupDir(const std::string& name) { return ScratchDir("group_" + name); }

SimGroupExtras OverModbus(const std::string& dir, int stall_ms, std::string* config, const std::string& group) {
  constexpr double kCountsPerM = 104857600.0, kLegSpeedMS = 0.5;
  SimGroupExtras extras;
  extras.group = group;
  extras.edit = [stall_ms](GroupFileEditor& g) {
    g.SetArg("drive_sim", "--fieldbus-timeout-ms", std::to_string(stall_ms))
        .SetArg("drive_sim", "--following-window-counts",
                fmt::format("{:.0f}", kLegSpeedMS * stall_ms * 1e-3 * kCountsPerM));
  };
  std::string text = ReadTextFile(SourcePath("") + kDefaultConfig);
  const std::string key = fmt::format("counts_per_m = {:.0f}", kCountsPerM);
  const std::size_t at = text.find(key);
  config->clear();
  if (at == std::string::npos) return extras;
  text.insert(at + key.size(), fmt::format("\nresponse_timeout_ms = {}", stall_ms));
  *config = dir + "/modbus.toml";
  std::ofstream(*config) << text;
  return extras;
}

namespace {

struct CpuTicks {
  std::uint64_t total = 0;
  std::uint64_t steal = 0;
};

// All CPUs' ticks from /proc/stat's first line (user nice system idle
// iowait irq softirq steal ...).
CpuTicks ReadCpuTicks() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  CpuTicks t;
  stat >> cpu;
  for (int field = 0; field < 8; ++field) {
    std::uint64_t v = 0;
    if (!(stat >> v)) break;
    t.total += v;
    if (field == 7) t.steal = v;
  }
  return t;
}

// How long this process's CPU cgroup has been throttled so far (ns): the
// periods in which a CPU quota was spent and nothing in it ran (cgroup v1
// cpu.stat throttled_time, v2 throttled_usec); 0 without a quota.
std::uint64_t ThrottledNs() {
  std::ifstream self("/proc/self/cgroup");
  std::string line;
  std::vector<std::pair<std::string, std::string>> stats;  // file, key
  while (std::getline(self, line)) {
    const std::size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1), path = line.substr(second + 1);
    if (controllers.empty()) stats.emplace_back("/sys/fs/cgroup" + path + "/cpu.stat", "throttled_usec");
    if (("," + controllers + ",").find(",cpu,") != std::string::npos) {
      stats.emplace_back("/sys/fs/cgroup/cpu" + path + "/cpu.stat", "throttled_time");
    }
  }
  for (const auto& [file, key] : stats) {
    std::ifstream stat(file);
    std::string name;
    std::uint64_t value = 0;
    while (stat >> name >> value) {
      if (name == key) return key == "throttled_usec" ? value * 1000 : value;
    }
  }
  return 0;
}

}  // namespace

GroupRun LaunchSimGroup(const std::string& name, const std::string& pr_mode, const std::string& planner_args,
                        const std::function<void(const std::string& dir)>& during, std::int64_t session_id,
                        const std::string& config, int stale_ms, const SimGroupExtras& extras) {
  const std::string dir = SimGroupDir(name);
  std::system(("mkdir -p " + dir).c_str());
  GroupRun run;
  run.dir = dir;
  run.log_path = extras.log_path.empty() ? dir + "/run.lcmlog" : extras.log_path;
  const std::string stale = std::to_string(stale_ms);
  GroupFileEditor group = GroupFileEditor::Load(SourcePath("deploy/groups/") + extras.group + ".toml");
  group.SetGroup("name", name)
      .SetGroup("config", config.front() == '/' ? config : SourcePath("") + config)
      .SetGroup("session_id", session_id)
      .SetTransport("lcm_url", kGroupLcmUrl)
      .SetTransport("shm_prefix", fmt::format("edsp.test.{}.{}", ::getpid(), name))
      .SetArg("rig", "--tracker-noise-m", "0")
      .SetArg("actuator_bridge", "--stale-ms", stale)
      .SetArg("kinematics", "--pr-mode", pr_mode)
      .SetArg("kinematics", "--stale-ms", stale)
      .SetArg("logger", "--output", run.log_path)
      .ReplaceArgs("planner", ParseArgList(planner_args));
  if (extras.edit) extras.edit(group);
  group.Write(dir + "/group.toml");
  const std::string command = fmt::format("{} {}/group.toml --until-exit planner --duration-s 120 2>{}/launch.err",
                                          BuiltProgram("edsp-launch"), dir, dir);
  std::thread action;
  run.launch_utime = UtimeNow();
  const CpuTicks before = ReadCpuTicks();
  const std::uint64_t throttled_before = ThrottledNs();
  if (during) action = std::thread([&] { during(dir); });
  const int status = std::system(command.c_str());
  if (action.joinable()) action.join();
  const CpuTicks after = ReadCpuTicks();
  const std::int64_t elapsed_us = UtimeNow() - run.launch_utime;
  if (elapsed_us > 0) {
    run.throttled_fraction =
        static_cast<double>(ThrottledNs() - throttled_before) * 1e-3 / static_cast<double>(elapsed_us);
  }
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (after.total > before.total) {
    run.steal_fraction =
        static_cast<double>(after.steal - before.steal) / static_cast<double>(after.total - before.total);
  }
  return run;
}

std::int64_t DeadlineMisses(const std::string& log_path, const std::string& node) {
  LogReader reader(log_path);
  LogEvent event;
  std::int64_t misses = 0;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_STATUS") continue;
    node_status_t s;
    if (s.decode(event.data.data(), 0, static_cast<int>(event.data.size())) >= 0 && s.node == node) {
      misses = std::max(misses, s.deadline_misses);
    }
  }
  return misses;
}

std::int64_t PlannerDeadlineMisses(const std::string& log_path) { return DeadlineMisses(log_path, "planner"); }

std::string FaultLines(const std::string& log_path) {
  LogReader reader(log_path);
  LogEvent event;
  std::string lines;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_FAULT") continue;
    fault_t f;
    if (f.decode(event.data.data(), 0, static_cast<int>(event.data.size())) < 0) continue;
    lines += fmt::format("{} {} {} code {}: {}\n", f.utime, f.node, f.channel, f.code, f.reason);
  }
  return lines;
}

std::string UnexplainedFaultLines(const std::string& log_path, bool count_info) {
  // The bridge's cumulative deadline misses at each of its EDSP_STATUS (1 Hz).
  std::vector<std::pair<std::int64_t, std::int64_t>> bridge_misses;  // utime, misses so far
  std::vector<fault_t> faults;
  std::int64_t last_setpoint_utime = 0;
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    const int size = static_cast<int>(event.data.size());
    EdspHeader header;
    if (event.channel == "EDSP_SETPOINT" && ParseEdspHeader(event.data, &header)) {
      last_setpoint_utime = std::max(last_setpoint_utime, header.utime);
    }
    if (event.channel == "EDSP_STATUS") {
      node_status_t st;
      if (st.decode(event.data.data(), 0, size) >= 0 && st.node == "actuator_bridge") {
        bridge_misses.emplace_back(st.utime, st.deadline_misses);
      }
    } else if (event.channel == "EDSP_FAULT") {
      fault_t f;
      if (f.decode(event.data.data(), 0, size) >= 0) faults.push_back(f);
    }
  }
  // A 20 ms stall of the bridge's thread misses at least 19 of its cycles,
  // counted on its first status after the trip against its last before.
  auto bridge_stalled_around = [&](std::int64_t utime) {
    std::int64_t before = 0, after = -1;
    for (const auto& [at, misses] : bridge_misses) {
      if (at <= utime) before = misses;
      if (at >= utime) {
        after = misses;
        break;
      }
    }
    return after - before >= 19;
  };
  std::string lines;
  bool explained_trips = true;  // the "commands again" note goes with its trip
  bool tripped = false;         // a rejoin follows a hold: a drive trip or a stale stream
  for (const fault_t& f : faults) {
    // The planner's program over, the group is stopped member by member: a
    // bridge still running past its stale limit then holds, as it must, on
    // a stream that ended (a slow shutdown of the members before it).
    const bool stream_ended = f.node == "actuator_bridge" && f.code == static_cast<std::int32_t>(FaultCode::kLatched) &&
                              f.utime > last_setpoint_utime;
    if (stream_ended) continue;
    const bool watchdog = f.node == "rig" && f.code == static_cast<std::int32_t>(FaultCode::kStale);
    if (watchdog && f.severity != fault_t::SEVERITY_INFO) {
      explained_trips = bridge_stalled_around(f.utime);
      tripped = true;
    }
    // The bridge following the stream again after the drives held (or after
    // its own stale hold) is the end of that trip, explained with it.
    const bool rejoin = f.node == "actuator_bridge" && f.code == static_cast<std::int32_t>(FaultCode::kStale) &&
                        f.severity == fault_t::SEVERITY_INFO;
    const bool explained_rejoin = rejoin && ((tripped && explained_trips) || bridge_stalled_around(f.utime));
    if ((watchdog && explained_trips) || explained_rejoin) continue;
    if (!count_info && f.severity == fault_t::SEVERITY_INFO) continue;
    lines += fmt::format("{} {} {} code {}: {}\n", f.utime, f.node, f.channel, f.code, f.reason);
  }
  return lines;
}

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
          previous.phase == pose_setpoint_t::PHASE_DWELL) {
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
  const std::string faults = UnexplainedFaultLines(run.log_path);
  EXPECT_TRUE(faults.empty()) << "faults were raised (edsp-log faults " << run.log_path << "):\n" << faults;
  const ChannelSummary& commands = summary.channels.at("EDSP_LEG_COMMAND");
  EXPECT_GT(commands.messages, 10000);
  // 1 kHz on an absolute clock: every cycle of the run is either a command
  // or a deadline the planner reports it missed (this virtual machine
  // sometimes stalls for milliseconds; a missed cycle is counted, not lost).
  const std::int64_t misses = PlannerDeadlineMisses(run.log_path);
  const double cycles = static_cast<double>(commands.last_utime - commands.first_utime) * 1e-3;
  EXPECT_NEAR(static_cast<double>(commands.messages + commands.seq_gaps + misses), cycles, 0.02 * cycles)
      << commands.messages << " commands, " << commands.seq_gaps << " lost, " << misses
      << " planner deadline misses in " << cycles << " cycles";
  ::testing::Test::RecordProperty("planner_deadline_misses", static_cast<int>(misses));
  // Loss on loopback multicast on this loaded 2-core machine: usually none,
  // occasionally one burst of up to ~30 ms (open in the multi-host issue,
  // which requires zero). Bounded at 1%, plus the share of the run in which
  // nothing of the group could run: what the hypervisor stole, and what a
  // CPU quota throttled (a logger not running loses what overflows
  // meanwhile; 29% stolen saw 1-3% lost), so a broken logger or a
  // systematic loss still fails, while that known burst does not make the
  // suite flaky.
  const double stalled = run.steal_fraction + run.throttled_fraction;
  for (const char* channel : {"EDSP_LEG_COMMAND", "EDSP_SETPOINT", "EDSP_TRACKER"}) {
    const ChannelSummary& c = summary.channels.at(channel);
    EXPECT_LE(static_cast<double>(c.seq_gaps), static_cast<double>(c.messages) * (0.01 + stalled))
        << channel << " (the hypervisor stole " << run.steal_fraction * 100.0 << "% of the run, a CPU quota throttled "
        << run.throttled_fraction * 100.0 << "%)";
    ::testing::Test::RecordProperty(std::string(channel) + "_seq_gaps", static_cast<int>(c.seq_gaps));
  }
  EXPECT_GT(summary.channels.at("EDSP_CONFIG").messages, 5);
}

}  // namespace edsp::test_support
