// edsp-bench-cueing-live: the cueing's transport delay on the live
// sim-cueing group (rig, actuator bridge, kinematics, logger, planner and
// edsp-cueing as processes, launched here in a private network namespace):
// a vehicle model's stand-in sends the braking manoeuvre over UDP at
// 249.9 Hz (a host clock that is not the stack's: its samples land at
// every phase of the 1 kHz cycle), and each sample is traced through the
// log from its send to the bridge's write of a command made from it
// (edsp-cueing delay). Target: p99 ≤ 5 ms (docs/cueing.md).
//   edsp-bench-cueing-live [--runs 3] [--json]
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/node/build_paths.h"
#include "edsp/transport/private_network.h"
#include "group_file_editor.h"

namespace edsp {
namespace {

constexpr double kTargetP99Ms = 5.0;
// Samples sent that a run must trace (the rest: sent before the engage or
// after the disengage).
constexpr double kTracedShare = 0.75;

std::string BinDir() { return std::filesystem::canonical("/proc/self/exe").parent_path().string(); }

// The shipped sim-cueing group in `dir`: its own shm prefix and log, the
// checkout's configs, the planner ending 2 s after the platform parked.
void WriteGroup(const std::string& dir) {
  GroupFileEditor group = GroupFileEditor::Load(SourcePath("deploy/groups/sim-cueing.toml"));
  group.SetGroup("config", SourcePath("config/huang2021.toml"))
      .SetTransport("shm_prefix", fmt::format("edsp.benchcueing.{}", ::getpid()))
      .SetArg("logger", "--output", dir + "/run.lcmlog")
      .SetArg("cueing", "--cueing", SourcePath("config/cueing.toml"))
      .SetArg("planner", "--exit-after-hold-s", "2");
  group.Write(dir + "/group.toml");
}

int Run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// One run: the group launched, the manoeuvre sent once the planner's status
// says idle (the bridge follows: an engage before it is refused), its
// packets engage the platform, the planner ends the group after the parking.
nlohmann::json RunOnce(int index) {
  const std::string dir = fmt::format("/tmp/edsp_bench_cueing_{}_{}", ::getpid(), index);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  WriteGroup(dir);
  const std::string bin = BinDir();
  const int launched = Run(fmt::format(
      "cd {src} && {bin}/edsp-launch {dir}/group.toml --bin-dir {bin} --until-exit planner "
      "2>{dir}/launch.err & launch=$!; "
      "for i in $(seq 300); do {bin}/edsp-ctl --group {dir}/group.toml --answer-timeout-s 2 status --json "
      "2>/dev/null | grep -q '\"state\":\"idle\"' && break; sleep 0.2; done; "
      "{bin}/edsp-cueing send --manoeuvre {src}/config/manoeuvres/braking.toml --rate-hz 249.9 --lead-s 5 "
      "--after disengage --tail-s 3 --sent-log {dir}/sent.csv 2>{dir}/send.err || kill -INT $launch; wait $launch",
      fmt::arg("src", SourceDir()), fmt::arg("bin", bin), fmt::arg("dir", dir)));
  if (launched != 0)
    throw std::runtime_error(fmt::format("run {}: the group ended with {} (see {})", index, launched, dir));
  if (Run(fmt::format("{}/edsp-cueing delay --log {d}/run.lcmlog --sent {d}/sent.csv --json >{d}/delay.json", bin,
                      fmt::arg("d", dir))) != 0) {
    throw std::runtime_error(fmt::format("run {}: no sample traced (see {})", index, dir));
  }
  std::ifstream in(dir + "/delay.json");
  nlohmann::json result = nlohmann::json::parse(in);
  // A p99 of the few samples traced says nothing of the rest.
  const double traced = result["samples_traced"].get<double>(), sent = result["samples_sent"].get<double>();
  if (!(traced >= kTracedShare * sent)) {
    throw std::runtime_error(fmt::format("run {}: {} of {} samples traced, fewer than {:.0f}% (see {})", index, traced,
                                         sent, kTracedShare * 100.0, dir));
  }
  std::filesystem::remove(dir + "/run.lcmlog");  // tens of MB; the rest stays
  return result;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-bench-cueing-live: vehicle sample → drive write on the live sim-cueing group"};
  int runs = 3;
  bool json = false;
  app.add_option("--runs", runs, "launches of the group (each 16 s of packets)")->check(CLI::Range(1, 100));
  app.add_flag("--json", json, "print JSON");
  CLI11_PARSE(app, argc, argv);
  try {
    edsp::EnterPrivateNetworkNamespace();
    nlohmann::json all = nlohmann::json::array();
    std::vector<double> p99s;
    for (int i = 0; i < runs; ++i) {
      std::fprintf(stderr, "edsp-bench-cueing-live: run %d of %d, braking at 249.9 Hz\n", i + 1, runs);
      all.push_back(edsp::RunOnce(i));
      p99s.push_back(all.back()["delay_p99_ms"].get<double>());
    }
    std::sort(p99s.begin(), p99s.end());
    const double median_p99 = p99s[p99s.size() / 2];
    const nlohmann::json out = {{"runs", all},
                                {"delay_p99_ms", median_p99},
                                {"target_p99_ms", edsp::kTargetP99Ms},
                                {"meets_target", median_p99 <= edsp::kTargetP99Ms}};
    if (json) {
      std::printf("%s\n", out.dump(2).c_str());
    } else {
      for (const auto& r : all) {
        std::printf("%lld of %lld samples traced: delay p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
                    r["samples_traced"].get<long long>(), r["samples_sent"].get<long long>(),
                    r["delay_p50_ms"].get<double>(), r["delay_p99_ms"].get<double>(), r["delay_max_ms"].get<double>());
      }
      std::printf("vehicle sample -> drive write p99 (median of %d runs): %.2f ms, target <= %.0f ms: %s\n", runs,
                  median_p99, edsp::kTargetP99Ms, median_p99 <= edsp::kTargetP99Ms ? "met" : "MISSED");
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-bench-cueing-live: error: %s\n", e.what());
    return 1;
  }
}
