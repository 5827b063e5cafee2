#include "multihost_group.h"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <cstring>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/node/group_file.h"
#include "edsp/node_status_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/transport/seq_gap.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp::test_support {

void Pause(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

namespace {

template <typename Msg, typename Fn>
void ForEach(const std::string& log_path, const std::string& channel, Fn fn) {
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel != channel) continue;
    Msg msg;
    if (msg.decode(event.data.data(), 0, static_cast<int>(event.data.size())) >= 0) fn(msg);
  }
}

}  // namespace

MultiHostGroup::MultiHostGroup(const VirtualNetwork& network, const std::string& name, MultiHostOptions options)
    : network_(network), options_(std::move(options)), dir_(test_support::ScratchDir("multihost_" + name)) {
  std::system(("rm -rf " + dir_ + " && mkdir -p " + dir_).c_str());
  const std::string config = options_.drives_over_modbus ? ModbusConfig() : SourcePath("config/huang2021.toml");
  const std::string stale = std::to_string(options_.stale_ms);
  GroupFileEditor group = GroupFileEditor::Load(SourcePath("deploy/groups/multihost.toml"));
  group.SetGroup("name", name)
      .SetGroup("config", config)
      .SetGroup("session_id", options_.session_id)
      .SetTransport("shm_prefix", "edsp.mh")
      .SetArg("rig", "--tracker-noise-m", "0")
      .SetArg("actuator_bridge", "--latency-report", latency_path())
      .SetArg("actuator_bridge", "--stale-ms", stale)
      .SetArg("kinematics", "--stale-ms", stale)
      .SetArg("logger", "--output", log_path())
      .ReplaceArgs("planner", ParseArgList(options_.planner_args));
  PlaceMembers(&group);
  group.Write(group_path());
}

// The shipped hosts renamed to the test's (several may be one), and the
// rig and the bridge beside it on the drive host (its process image in that
// host's shared memory); or, over Modbus TCP, the rig and edsp-drive-sim
// there with the bridge on the controller, their process image the Modbus
// TCP link between hosts.
void MultiHostGroup::PlaceMembers(GroupFileEditor* group) const {
  group->RemoveHosts();
  for (const std::string& host :
       std::set<std::string>{options_.operator_host, options_.controller_host, options_.drive_host}) {
    group->SetHost(host, "eth0");
  }
  group->SetMember("rig", "host", options_.drive_host)
      .SetMember("actuator_bridge", "host", options_.drive_host)
      .SetMember("kinematics", "host", options_.controller_host)
      .SetMember("logger", "host", options_.operator_host)
      .SetMember("planner", "host", options_.operator_host);
  if (!options_.drives_over_modbus) return;
  // The drives' following window: a leg's travel at 0.5 m/s over the stale
  // limit, so that only the fault a test injects trips them.
  constexpr double kCountsPerM = 104857600.0, kLegSpeedMS = 0.5;
  group
      ->InsertMember(
          "rig", "drive_sim", "edsp-drive-sim",
          {"--axes", "rig", "--host", network_.Address(options_.drive_host), "--port", std::to_string(kModbusPort),
           "--fieldbus-timeout-ms", std::to_string(options_.stale_ms), "--following-window-counts",
           fmt::format("{:.0f}", kLegSpeedMS * options_.stale_ms * 1e-3 * kCountsPerM)})
      .SetMember("drive_sim", "host", options_.drive_host)
      .SetMemberList("drive_sim", "requires", std::vector<std::string>{"rig"})
      .SetMember("drive_sim", "start_delay_ms", 200)
      .SetMember("actuator_bridge", "host", options_.controller_host)
      .SetMemberList("actuator_bridge", "requires", std::vector<std::string>{})
      .AppendArgs("actuator_bridge", {"--backend", "modbus-tcp"});
}

// The shipped config with the drive host's server as the bridge's
// [drives] endpoint, its response timeout the stale limit.
std::string MultiHostGroup::ModbusConfig() const {
  std::ifstream in(SourcePath("config/huang2021.toml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string config = text.str();
  const std::string key = "counts_per_m = 104857600";
  const std::size_t at = config.find(key);
  if (at == std::string::npos) throw std::runtime_error("config/huang2021.toml: no [drives] " + key);
  config.insert(at + key.size(), fmt::format("\nhost = \"{}\"\nport = {}\nresponse_timeout_ms = {}",
                                             network_.Address(options_.drive_host), kModbusPort, options_.stale_ms));
  const std::string path = dir_ + "/modbus.toml";
  std::ofstream(path) << config;
  return path;
}

void MultiHostGroup::Start() {
  auto launch = [&](const std::string& host, const std::string& extra) {
    return network_.Spawn(host,
                          fmt::format("{} {} --host {} {}", BuiltProgram("edsp-launch"), group_path(), host, extra),
                          fmt::format("{}/launch.{}.err", dir_, host));
  };
  // One launcher per distinct host; the operator's last, until its planner exits.
  if (options_.drive_host != options_.operator_host) {
    drive_ = launch(options_.drive_host, "");
    Pause(600);
  }
  if (options_.controller_host != options_.operator_host && options_.controller_host != options_.drive_host) {
    controller_ = launch(options_.controller_host, "");
    Pause(400);
  }
  operator_ = launch(options_.operator_host, "--until-exit planner --duration-s 200");
}

int MultiHostGroup::Finish(int timeout_ms) {
  const int operator_exit = VirtualNetwork::Wait(operator_, timeout_ms);
  background_exits_.clear();
  for (pid_t pid : {controller_, drive_}) {
    if (pid > 0) background_exits_.push_back(VirtualNetwork::Stop(pid));
  }
  return operator_exit;
}

std::unique_ptr<GroupWatch> MultiHostGroup::WatchFrom(const std::string& host, const std::string& channels) const {
  const std::string lcm_url = LoadTransportConfig(group_path()).lcm_url;
  const std::string ns_path = "/var/run/netns/" + network_.Namespace(host);
  std::unique_ptr<GroupWatch> watch;
  std::string error;
  // A thread of its own enters the namespace (setns moves only the calling
  // thread); the watch's socket and its listener, started from there, stay in it.
  std::thread([&] {
    const int fd = ::open(ns_path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::setns(fd, CLONE_NEWNET) != 0) {
      error = fmt::format("cannot enter {}: {}", ns_path, std::strerror(errno));
    } else {
      watch = std::make_unique<GroupWatch>(lcm_url, channels);
      if (!watch->ok()) error = fmt::format("no LCM on {} in {}", lcm_url, ns_path);
    }
    if (fd >= 0) ::close(fd);
  }).join();
  if (!error.empty()) throw std::runtime_error("watch from host " + host + ": " + error);
  return watch;
}

int MultiHostGroup::Ctl(const std::string& host, const std::string& arguments) const {
  return network_.Run(host, fmt::format("{} {} --session-id {} --group {} >>{}/ctl.out 2>&1", BuiltProgram("edsp-ctl"),
                                        arguments, options_.session_id, group_path(), dir_));
}

std::vector<TruthSample> TruthOf(const std::string& log_path) {
  std::vector<TruthSample> out;
  ForEach<rig_truth_t>(log_path, "EDSP_RIG_TRUTH", [&](const rig_truth_t& t) {
    TruthSample s{t.utime, t.seq, {}, {}};
    std::copy(t.pose, t.pose + 6, s.pose);
    std::copy(t.leg_length_m, t.leg_length_m + 6, s.leg_length_m);
    out.push_back(s);
  });
  return out;
}

std::vector<fault_t> FaultsOf(const std::string& log_path) {
  std::vector<fault_t> out;
  ForEach<fault_t>(log_path, "EDSP_FAULT", [&](const fault_t& f) { out.push_back(f); });
  return out;
}

std::int64_t FirstReArmUtime(const std::string& log_path) {
  std::int64_t armed_utime = -1;
  ForEach<reply_t>(log_path, "EDSP_REPLY", [&](const reply_t& r) {
    if (r.node == "actuator_bridge" && r.code == reply_t::CODE_DONE && armed_utime < 0) armed_utime = r.utime;
  });
  return armed_utime;
}

std::string Describe(const std::vector<fault_t>& faults) {
  std::string lines;
  for (const fault_t& f : faults)
    lines += fmt::format("{} {} {} code {}: {}\n", f.utime, f.node, f.channel, f.code, f.reason);
  return lines;
}

std::int64_t StatusDrops(const std::string& log_path, const std::string& node) {
  std::int64_t drops = 0;
  ForEach<node_status_t>(log_path, "EDSP_STATUS", [&](const node_status_t& s) {
    if (s.node == node) drops = std::max(drops, s.drops);
  });
  return drops;
}

std::map<std::string, std::int64_t> StatusGapsByNode(const std::string& log_path) {
  std::map<std::string, std::int64_t> gaps, last;
  ForEach<node_status_t>(log_path, "EDSP_STATUS", [&](const node_status_t& s) {
    const auto [it, fresh] = last.emplace(s.node, s.seq);
    gaps[s.node] += fresh ? 0 : SeqGap(it->second, s.seq);
    it->second = s.seq;
  });
  return gaps;
}

namespace {

// The largest of `distance` between consecutive truth samples within the
// window, shared among the cycles whose samples the log lost.
template <typename Distance>
double LargestPerCycle(const std::vector<TruthSample>& truth, std::int64_t from_utime, std::int64_t to_utime,
                       Distance distance) {
  double largest = 0.0;
  for (std::size_t i = 1; i < truth.size(); ++i) {
    if (truth[i - 1].utime < from_utime || truth[i].utime > to_utime) continue;
    const std::int64_t cycles = std::max<std::int64_t>(1, truth[i].seq - truth[i - 1].seq);
    largest = std::max(largest, distance(truth[i - 1], truth[i]) / static_cast<double>(cycles));
  }
  return largest;
}

}  // namespace

double LargestTrueStep(const std::vector<TruthSample>& truth, std::int64_t from_utime, std::int64_t to_utime) {
  return LargestPerCycle(truth, from_utime, to_utime, [](const TruthSample& a, const TruthSample& b) {
    return std::hypot(b.pose[0] - a.pose[0], b.pose[1] - a.pose[1], b.pose[2] - a.pose[2]);
  });
}

double LargestTrueLegStep(const std::vector<TruthSample>& truth, std::int64_t from_utime, std::int64_t to_utime) {
  return LargestPerCycle(truth, from_utime, to_utime, [](const TruthSample& a, const TruthSample& b) {
    double largest = 0.0;
    for (int i = 0; i < 6; ++i) largest = std::max(largest, std::abs(b.leg_length_m[i] - a.leg_length_m[i]));
    return largest;
  });
}

namespace {

// A stall of the loops around the bridge: when it ended, how late.
struct Stall {
  std::int64_t end_utime;
  std::int64_t late_us;
};

// Late cycles of the commands the bridge took and of its own (their stamps),
// and stands of the rig emulator (its truth unreceived while the bridge's
// readings kept coming: a stalled logger is no stalled rig).
std::vector<Stall> StallsAroundTheBridge(const std::string& log_path) {
  constexpr std::int64_t kPeriodUs = 1000;
  std::vector<Stall> stalls;
  std::map<std::string, EdspHeader> last;
  std::int64_t last_truth = -1, last_reading = -1, widest_reading_gap = 0;
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    const std::int64_t t = event.timestamp_utime;
    if (event.channel == "EDSP_LEG_STATE") {
      if (last_truth >= 0) widest_reading_gap = std::max(widest_reading_gap, t - std::max(last_reading, last_truth));
      last_reading = t;
    }
    if (event.channel == "EDSP_RIG_TRUTH") {
      const std::int64_t silence = t - last_truth;
      if (last_truth >= 0 && silence > kPeriodUs && last_reading > last_truth && widest_reading_gap < silence / 4) {
        stalls.push_back({t, silence - kPeriodUs});
      }
      last_truth = t;
      widest_reading_gap = 0;
      continue;
    }
    if (event.channel != "EDSP_SETPOINT" && event.channel != "EDSP_LEG_COMMAND" && event.channel != "EDSP_LEG_STATE")
      continue;
    EdspHeader header;
    if (!ParseEdspHeader(event.data, &header)) continue;
    const auto [it, fresh] = last.emplace(event.channel, header);
    if (!fresh && header.seq == it->second.seq + 1 && header.utime - it->second.utime > kPeriodUs) {
      stalls.push_back({header.utime, header.utime - it->second.utime - kPeriodUs});
    }
    it->second = header;
  }
  return stalls;
}

}  // namespace

std::string LegStepCheck::Describe() const {
  return fmt::format("a leg moved {:.1f} µm in a cycle at {}, {:.1f} µm allowed there", step_m * 1e6, utime,
                     allowed_m * 1e6);
}

LegStepCheck CheckLegSteps(const std::string& log_path, const std::vector<TruthSample>& truth, std::int64_t from_utime,
                           std::int64_t to_utime) {
  constexpr std::int64_t kCatchUpUs = 50000;
  static const double leg_speed_m_s = LoadConfigFile(SourcePath("config/huang2021.toml")).limits.leg_speed_max_m_s;
  const std::vector<Stall> stalls = StallsAroundTheBridge(log_path);
  LegStepCheck check;
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const TruthSample &a = truth[i - 1], &b = truth[i];
    if (a.utime < from_utime || b.utime > to_utime) continue;
    const std::vector<TruthSample> pair = {a, b};
    const double step = LargestTrueLegStep(pair);
    std::int64_t late_us = 0;
    for (const Stall& stall : stalls) {
      if (stall.end_utime >= b.utime - kCatchUpUs && stall.end_utime <= b.utime + 1000)
        late_us = std::max(late_us, stall.late_us);
    }
    const double allowed = leg_speed_m_s * (1e-3 + static_cast<double>(late_us) * 1e-6);
    if (step / allowed > check.worst_ratio) check = {step / allowed, step, allowed, b.utime};
  }
  return check;
}

std::vector<double> LastSetpoint(const std::string& log_path) {
  std::vector<double> pose(6, 0.0);
  ForEach<pose_setpoint_t>(log_path, "EDSP_SETPOINT",
                           [&](const pose_setpoint_t& s) { pose.assign(s.pose, s.pose + 6); });
  return pose;
}

}  // namespace edsp::test_support
