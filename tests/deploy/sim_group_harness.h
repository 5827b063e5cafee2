#pragma once
// The sim group as real processes for the multi-process tests: the shipped
// group file (deploy/groups/sim.toml) with the test's changes (noise-free
// tracker, its PR mode, stale limit and planner arguments, its own shm
// prefix and session), started by edsp-launch until the planner exits,
// with an action run meanwhile; then the log's health.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "edsp/kinematics/platform_model.h"
#include "edsp/logger/log_reader.h"
#include "group_file_editor.h"

namespace edsp::test_support {

struct GroupRun {
  int exit_code = -1;
  std::int64_t launch_utime = 0;  // edsp-launch started (UtimeNow)
  std::string log_path;           // <dir>/run.lcmlog unless SimGroupExtras::log_path
  std::string dir;                // group.toml, launch.err
  // The share of the run's CPU time the hypervisor took (/proc/stat steal,
  // both CPUs): a virtual machine's neighbours stall every process at once.
  double steal_fraction = 0.0;
  // The share of the run's wall time a CPU quota throttled this process's
  // cgroup (cpu.stat): every member stopped until the next period.
  double throttled_fraction = 0.0;
};

inline constexpr const char* kDefaultPlannerArgs =
    R"("--motions", "Lz,Rz", "--stops", "3", "--dwell-s", "0.6", "--max-speed-m-s", "0.25",
        "--max-speed-rad-s", "0.5", "--exit-after-hold-s", "0.3")";

// Where the group's LCM traffic is (multicast on the test's private
// loopback, ttl 0), for a GroupWatch.
inline constexpr const char* kGroupLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

// Relative to the checkout, or an absolute path (a test's own config).
inline constexpr const char* kDefaultConfig = "config/huang2021.toml";

// The nodes' stale limit as shipped: what the hold tests exercise.
inline constexpr int kShippedStaleMs = 50;
// For tests of accuracy, not of holding: a shared machine can stall a node
// past 50 ms, which latches the bridge mid-motion, a correct hold but not
// what those tests measure.
inline constexpr int kStallTolerantStaleMs = 250;

// What some tests change beyond the planner: the shipped group they start
// from, anything else of the group file (a channel's route, a member's
// arguments, through GroupFileEditor), and where the log goes.
struct SimGroupExtras {
  std::string group = "sim";  // deploy/groups/<group>.toml
  std::function<void(GroupFileEditor&)> edit;
  std::string log_path;  // default <dir>/run.lcmlog
};

// The group over Modbus TCP, deploy/groups/sim-modbus.toml (edsp-drive-sim
// after the rig, the bridge its Modbus master), in a copy of the shipped
// config written to `dir`, returned in *config ("" if the shipped config
// declares no [drives] counts_per_m). A stall of `stall_ms` is tolerated:
// the master's response timeout and the drives' fieldbus timeout are that
// long, and their following-error window is a leg's travel at 0.5 m/s
// meanwhile (a drive simulator descheduled for 10 ms while the rig moves
// the legs at 0.25 m/s falls 2.5 mm behind its target: past the shipped
// 1.9 mm window, a fault). `group`: sim-modbus,
// or sim-cia402 (the same drives over the shared-memory CSP image).
SimGroupExtras OverModbus(const std::string& dir, int stall_ms, std::string* config,
                          const std::string& group = "sim-modbus");

// `during(dir)` runs on a thread while the group does. `stale_ms` goes to the
// kinematics node and the actuator bridge.
GroupRun LaunchSimGroup(const std::string& name, const std::string& pr_mode,
                        const std::string& planner_args = kDefaultPlannerArgs,
                        const std::function<void(const std::string& dir)>& during = {}, std::int64_t session_id = 77,
                        const std::string& config = kDefaultConfig, int stale_ms = kShippedStaleMs,
                        const SimGroupExtras& extras = {});

// The run directory LaunchSimGroup uses for `name` (it exists once launched).
std::string SimGroupDir(const std::string& name);

// Every EDSP_FAULT of a log as "node channel code: reason" lines.
std::string FaultLines(const std::string& log_path);

// The same, less the rig's drive-watchdog reports that the bridge's own
// clock explains: a drive left 20 ms without a command while the bridge's
// thread missed that many cycles (EDSP_STATUS deadline_misses, its status
// before the trip against the one after) is the machine's stall, not a
// silent bridge; a bridge that skipped writes on time still shows.
std::string UnexplainedFaultLines(const std::string& log_path, bool count_info = true);

// Launcher exit 0, no faults, commands at 1 kHz, loss bounded (see .cpp).
void ExpectCleanRun(const GroupRun& run);

// The largest deadline-miss count `node` reported on EDSP_STATUS.
std::int64_t DeadlineMisses(const std::string& log_path, const std::string& node);
std::int64_t PlannerDeadlineMisses(const std::string& log_path);

struct DwellEnd {
  std::string segment;
  Pose target;
  double miss_m;
};
// The last tracker sample of every dwell against the target's point A.
std::vector<DwellEnd> DwellEnds(const std::string& log_path, const PlatformModel& model);

// Every message on `channel` of the log that decodes as a Msg, in order.
template <typename Msg>
std::vector<Msg> LoggedMessages(const std::string& log_path, const std::string& channel) {
  LogReader reader(log_path);
  LogEvent event;
  std::vector<Msg> out;
  while (reader.Next(&event)) {
    Msg m{};
    if (event.channel == channel && m.decode(event.data.data(), 0, static_cast<int>(event.data.size())) >= 0) {
      out.push_back(m);
    }
  }
  return out;
}

// Directory of a run (where group.toml and launch.err are; the log too
// unless SimGroupExtras::log_path put it elsewhere).
inline std::string RunDir(const GroupRun& run) { return run.dir; }

}  // namespace edsp::test_support
