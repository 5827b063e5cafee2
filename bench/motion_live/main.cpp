// edsp-bench-motion-live: the motion service as an operator's script sees
// it, through the live sim group (rig, actuator bridge, kinematics, logger,
// planner as processes, launched here in a private network namespace):
// moves of 10 mm back and forth, each sent as edsp-ctl sends it, timed
//   request → reply; request → first setpoint of the move (the status that
//   names it, published in the same cycle, right after that setpoint);
//   request → on target.
// Once with the motion channels on LCM (as shipped), once on shared-memory
// rings. Targets: request → first setpoint p99 ≤ 2 ms over LCM.
//   edsp-bench-motion-live [--moves 100] [--transport lcm|shm|lcm,shm] [--json]
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/leg_state_t.hpp"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/group_file.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"
#include "edsp/transport/private_network.h"
#include "edsp/transport/transport_config.h"
#include "group_file_editor.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::int64_t kSession = 4242;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// The shipped sim group (the planner idle), in `dir`, its own shm prefix.
// Over shared memory the motion channels ride rings (mirrored on LCM for
// the logger and lcm-spy): a ring has one writer, so such a group serves
// this one client; the shipped groups keep requests on LCM for any number.
std::string WriteGroup(const std::string& dir, bool over_shm) {
  GroupFileEditor group = GroupFileEditor::Load(SourcePath("deploy/groups/sim.toml"));
  group.SetGroup("name", "bench-motion")
      .SetGroup("config", SourcePath("config/huang2021.toml"))
      .SetGroup("session_id", kSession)
      .SetTransport("shm_prefix", fmt::format("edsp.benchmotion.{}", ::getpid()))
      .SetArg("logger", "--output", dir + "/run.lcmlog");
  if (over_shm) {
    for (const char* channel : {channel::kMotionRequest, channel::kMotionReply, channel::kMotionStatus}) {
      group.SetChannel(channel, "path", "both");
    }
  }
  group.Write(dir + "/group.toml");
  return dir + "/group.toml";
}

pid_t Launch(const std::string& group, const std::string& dir) {
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string command =
        fmt::format("exec {}/edsp-launch {} --bin-dir {} --duration-s 3600 2>{}/launch.err", bin, group, bin, dir);
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

struct Timing {
  double reply_ms, first_setpoint_ms, on_target_ms;
};

class Operator {
 public:
  // The request channel is advertised at once: on a ring, the planner's
  // reader finds it while the group starts, not at the first request
  // (which it would then miss: a reader starts at the ring's head).
  explicit Operator(const TransportConfig& transport)
      : bus_(transport), requests_(bus_.Advertise<motion_request_t>(channel::kMotionRequest)) {
    bus_.Subscribe<motion_status_t>(channel::kMotionStatus, [this](const motion_status_t& s) {
      if (s.session_id != kSession) return;
      last_ = s;
      if (awaited_ != 0 && s.request_id == awaited_ && !first_ && s.state == motion_status_t::STATE_MOVING) {
        first_ = Clock::now();
      }
      if (awaited_ != 0 && s.request_id == awaited_ && first_ && s.on_target && !on_target_) on_target_ = Clock::now();
    });
    // Ready once the bridge follows (every drive enabled): a move sent
    // during its start-up hold is refused.
    bus_.Subscribe<leg_state_t>(channel::kLegState, [this](const leg_state_t& legs) {
      following_ = std::all_of(std::begin(legs.drive_status), std::end(legs.drive_status),
                               [](std::int8_t d) { return d == leg_state_t::DRIVE_ENABLED; });
    });
    bus_.Subscribe<motion_reply_t>(channel::kMotionReply, [this](const motion_reply_t& r) {
      if (r.request_id == awaited_ && !reply_) {
        reply_ = Clock::now();
        accepted_ = r.accepted != 0;
        reason_ = r.reason;
      }
    });
  }

  void WaitReady(double seconds) {
    const auto until =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    while (Clock::now() < until) {
      bus_.Handle(std::chrono::milliseconds(20));
      if (last_ && last_->measured_valid && following_) return;
    }
    throw std::runtime_error("the group never measured its pose with the bridge following (see launch.err)");
  }

  Timing Move(double dx, std::int64_t id) {
    motion_request_t r{};
    r.seq = id;
    r.session_id = kSession;
    r.request_id = id;
    r.client = "edsp-bench-motion-live";
    r.kind = motion_request_t::KIND_MOVE;
    r.relative = true;
    r.pose[0] = dx;
    awaited_ = id;
    first_.reset(), on_target_.reset(), reply_.reset();
    const auto sent = Clock::now();
    auto resend = sent;
    const auto until = sent + std::chrono::seconds(30);
    while (!on_target_ && Clock::now() < until) {
      if (!reply_ && Clock::now() >= resend) {  // as edsp-ctl: again every 0.5 s until answered
        r.utime = UtimeNow();
        requests_.Publish(r);
        resend = Clock::now() + std::chrono::milliseconds(500);
      }
      bus_.Handle(std::chrono::milliseconds(1));
      if (reply_ && !accepted_) throw std::runtime_error("move refused: " + reason_);
    }
    if (!on_target_ || !first_ || !reply_) throw std::runtime_error(fmt::format("move {} not on target in 30 s", id));
    return {Ms(*reply_ - sent), Ms(*first_ - sent), Ms(*on_target_ - sent)};
  }

 private:
  Bus bus_;
  Bus::Publisher<motion_request_t> requests_;
  std::optional<motion_status_t> last_;
  bool following_ = false;
  std::int64_t awaited_ = 0;
  std::optional<Clock::time_point> first_, on_target_, reply_;
  bool accepted_ = false;
  std::string reason_;
};

double Quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

nlohmann::json Summary(const std::vector<double>& v) {
  return {{"p50_ms", Quantile(v, 0.5)}, {"p99_ms", Quantile(v, 0.99)}, {"max_ms", Quantile(v, 1.0)}};
}

// One launch of the group, `moves` moves through it.
nlohmann::json MeasureGroup(bool over_shm, int moves) {
  const std::string dir = fmt::format("/tmp/edsp_bench_motion_live_{}_{}", ::getpid(), over_shm ? "shm" : "lcm");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string group_file = WriteGroup(dir, over_shm);
  const pid_t group = Launch(group_file, dir);
  const auto stop = [group] {
    ::kill(group, SIGINT);
    ::waitpid(group, nullptr, 0);
  };
  try {
    Operator op(LoadTransportConfig(group_file));
    op.WaitReady(60.0);
    std::vector<double> reply, first, on_target;
    for (int k = 0; k < moves; ++k) {
      const Timing t = op.Move(k % 2 == 0 ? 0.01 : -0.01, 1000 + k);
      reply.push_back(t.reply_ms), first.push_back(t.first_setpoint_ms), on_target.push_back(t.on_target_ms);
    }
    stop();
    std::filesystem::remove_all(dir);
    return {{"transport", over_shm ? "shm" : "lcm"},
            {"moves", moves},
            {"request_to_reply", Summary(reply)},
            {"request_to_first_setpoint", Summary(first)},
            {"request_to_on_target_10mm", Summary(on_target)}};
  } catch (...) {
    stop();
    throw;
  }
}

void Print(const nlohmann::json& r) {
  for (const char* key : {"request_to_reply", "request_to_first_setpoint", "request_to_on_target_10mm"}) {
    std::printf("%-4s %-28s p50 %8.3f ms  p99 %8.3f ms  max %8.3f ms\n", r["transport"].get<std::string>().c_str(), key,
                r[key]["p50_ms"].get<double>(), r[key]["p99_ms"].get<double>(), r[key]["max_ms"].get<double>());
  }
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-bench-motion-live: request → first setpoint and → on target through the live sim group"};
  int moves = 100;
  bool json = false;
  std::string transports = "lcm,shm";
  app.add_option("--moves", moves, "10 mm moves, back and forth, per transport")->check(CLI::Range(2, 100000));
  app.add_option("--transport", transports, "lcm, shm or lcm,shm: the motion channels' path, one launch each")
      ->check(CLI::IsMember({"lcm", "shm", "lcm,shm"}));
  app.add_flag("--json", json, "print JSON");
  CLI11_PARSE(app, argc, argv);
  try {
    edsp::EnterPrivateNetworkNamespace();
    // The LCM figures at the top level (as they have always been), the
    // shared-memory ones under "over_shm".
    nlohmann::json result;
    if (transports != "shm") result = edsp::MeasureGroup(false, moves);
    if (transports != "lcm") {
      const nlohmann::json shm = edsp::MeasureGroup(true, moves);
      if (result.is_null())
        result = shm;
      else
        result["over_shm"] = shm;
    }
    result["target_first_setpoint_p99_ms"] = 2.0;
    if (json) {
      std::printf("%s\n", result.dump(2).c_str());
    } else {
      edsp::Print(result);
      if (result.contains("over_shm")) edsp::Print(result["over_shm"]);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-bench-motion-live: error: %s\n", e.what());
    return 1;
  }
}
