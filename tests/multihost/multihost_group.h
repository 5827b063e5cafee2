#pragma once
// The sim stack as a rig wires it, on a VirtualNetwork: operator (planner +
// logger), controller (kinematics), drive (actuator bridge + virtual rig;
// or, over Modbus TCP, the bridge on the controller and the drive
// simulator beside the rig), one edsp-launch per host, all from the shipped
// deploy/groups/multihost.toml with the test's changes. The
// logger on the operator host records every channel; the bridge writes its
// setpoint → drive latencies on exit.

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "edsp/fault_t.hpp"
#include "group_file_editor.h"
#include "group_watch.h"
#include "virtual_network.h"

namespace edsp::test_support {

inline constexpr std::int64_t kMultiHostSession = 4242;

struct MultiHostOptions {
  std::string planner_args;  // TOML array items
  std::int64_t session_id = kMultiHostSession;
  std::string operator_host = "operator";
  std::string controller_host = "controller";
  std::string drive_host = "drive";
  // The bridge's and kinematics' stale limit. The shipped 50 ms for the tests
  // of holding; for the others more, as in the single-host group tests: a
  // shared machine can deliver a command past 50 ms late, a correct hold
  // but not what those tests measure.
  int stale_ms = 250;
  // The drive cabinet as a fieldbus: the bridge moves to the controller and
  // is a Modbus TCP master of edsp-drive-sim on the drive host (which moves
  // the rig's legs there), at kModbusPort. The master's response timeout
  // and the drives' fieldbus timeout are the stale limit.
  bool drives_over_modbus = false;
};

inline constexpr int kModbusPort = 1502;

class MultiHostGroup {
 public:
  MultiHostGroup(const VirtualNetwork& network, const std::string& name, MultiHostOptions options);

  // Drive host first, then the controller, then the operator's logger and
  // planner (the operator's launcher stops when the planner exits): one
  // launcher per distinct host.
  void Start();
  // Waits for the operator's launcher, then stops the others in reverse
  // order; returns the operator launcher's exit status.
  int Finish(int timeout_ms = 240000);

  // The group's traffic as `host` sees it (EDSP_SETPOINT, EDSP_FAULT,
  // EDSP_RIG_TRUTH and `channels`): a GroupWatch made in that host's network
  // namespace, so that a test acts on what the group does, not on a pause
  // tuned to one machine's start-up. Throws std::runtime_error naming the
  // host if its namespace cannot be entered or the watch cannot listen.
  std::unique_ptr<GroupWatch> WatchFrom(const std::string& host, const std::string& channels = "") const;

  // edsp-ctl on `host`, in this group's session; returns its exit status.
  int Ctl(const std::string& host, const std::string& arguments) const;

  std::string dir() const { return dir_; }
  std::string log_path() const { return dir_ + "/run.lcmlog"; }
  std::string latency_path() const { return dir_ + "/latency.json"; }
  std::string group_path() const { return dir_ + "/group.toml"; }
  std::vector<int> background_exits() const { return background_exits_; }

 private:
  void PlaceMembers(GroupFileEditor* group) const;
  std::string ModbusConfig() const;

  const VirtualNetwork& network_;
  MultiHostOptions options_;
  std::string dir_;
  pid_t drive_ = -1, controller_ = -1, operator_ = -1;
  std::vector<int> background_exits_;
};

// Sleeps this thread for `ms` milliseconds.
void Pause(int ms);

// What the tests read back from the operator's log.
struct TruthSample {
  std::int64_t utime;
  std::int64_t seq;  // the rig numbers every cycle it runs
  double pose[6];
  double leg_length_m[6];
};
std::vector<TruthSample> TruthOf(const std::string& log_path);
std::vector<fault_t> FaultsOf(const std::string& log_path);
// The bridge's first reply that it re-armed (EDSP_REPLY), by its clock; -1 if none.
std::int64_t FirstReArmUtime(const std::string& log_path);
std::string Describe(const std::vector<fault_t>& faults);
// The largest `drops` a node reported on EDSP_STATUS.
std::int64_t StatusDrops(const std::string& log_path, const std::string& node);
// Messages missing from each node's EDSP_STATUS stream, by its seq.
std::map<std::string, std::int64_t> StatusGapsByNode(const std::string& log_path);
// The largest change of the true position in one cycle of the rig, m:
// between consecutive truth samples, shared among the cycles whose samples
// the log lost (a gap in the rig's seq: a burst of caught-up cycles may
// outrun the network), so a lost message is not taken for a jump.
double LargestTrueStep(const std::vector<TruthSample>& truth, std::int64_t from_utime = 0,
                       std::int64_t to_utime = INT64_MAX);
// The same of the legs' true lengths, m: the largest any leg changed in one
// cycle of the rig.
double LargestTrueLegStep(const std::vector<TruthSample>& truth, std::int64_t from_utime = 0,
                          std::int64_t to_utime = INT64_MAX);

// A leg's largest step in a cycle against what it may move then: the legs'
// speed limit ([limits] leg_speed_max_m_s of the shipped config) over the
// cycle and over the stall that ended within the 50 ms before (the bridge's
// commands late, its own cycles late, or the rig's drives standing). The
// bridge passes a command that moved at that speed over the whole time
// since the last one, and the drives close that gap in a few cycles; a
// jump (a bridge that rejoined the stream at once) needs no stall.
struct LegStepCheck {
  double worst_ratio = 0.0;  // the largest step / allowed of any cycle
  double step_m = 0.0;       // that cycle's step
  double allowed_m = 0.0;    // and what it was allowed
  std::int64_t utime = 0;    // when
  std::string Describe() const;
};
LegStepCheck CheckLegSteps(const std::string& log_path, const std::vector<TruthSample>& truth,
                           std::int64_t from_utime = 0, std::int64_t to_utime = INT64_MAX);
// The last setpoint's pose.
std::vector<double> LastSetpoint(const std::string& log_path);

}  // namespace edsp::test_support
