// edsp-bench-drives: what one Modbus TCP cycle costs here. Six simulated
// CiA 402 drives served by a child process (edsp's server, as
// edsp-drive-sim runs it), or by a server elsewhere (`--connect HOST:PORT`:
// an edsp-drive-sim on another host, or real drives); this process is the
// master and times N cycles of one read/write request (function 23: six
// RxPDOs out, six TxPDOs in), paced at the chosen period. `--link shm`
// times the same cycle over the shared-memory CSP image instead (the
// child an edsp-drive-sim --serve shm), whose exchange never waits for the
// drives: its inputs are those of their last cycle. Reports medians
// and tails from this run only; the machine's own timer baseline (a sleep
// of the same period) is measured beside it, so a busy machine shows as such.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/drives/csp_master.h"
#include "edsp/drives/csp_shm_image.h"
#include "edsp/drives/csp_shm_master.h"
#include "edsp/drives/csp_shm_server.h"
#include "edsp/drives/modbus_drive_master.h"
#include "edsp/drives/modbus_drive_server.h"

namespace {

using Clock = std::chrono::steady_clock;
using edsp::cia402::CspCommands;
using edsp::cia402::CspFeedbacks;

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

nlohmann::json Summary(const std::vector<double>& us) {
  return {{"samples", us.size()},
          {"p50_us", Percentile(us, 0.5)},
          {"p99_us", Percentile(us, 0.99)},
          {"p999_us", Percentile(us, 0.999)},
          {"max_us", us.empty() ? 0.0 : *std::max_element(us.begin(), us.end())}};
}

// How late a plain sleep of `period` wakes here: the timer baseline.
std::vector<double> SleepLateness(std::chrono::microseconds period, int n) {
  std::vector<double> late;
  late.reserve(static_cast<std::size_t>(n));
  auto next = Clock::now() + period;
  for (int k = 0; k < n; ++k) {
    std::this_thread::sleep_until(next);
    late.push_back(std::chrono::duration<double, std::micro>(Clock::now() - next).count());
    next += period;
  }
  return late;
}

// A child process serving six simulated drives on a free loopback port
// (or, `shm`, the CSP image under `prefix`); killed when this object goes
// (and with this process, whatever happens).
struct ChildServer {
  pid_t pid = -1;
  int port = 0;
  std::string segment;  // shm: the child's ring, removed after it is killed
  ChildServer(bool shm, const std::string& prefix) {
    if (shm) {
      segment = edsp::cia402::CspTxSpec(prefix, 0600).segment_name;
      // Its segment made in the child: the parent's copy of the server
      // would remove it on leaving this constructor (the master waits).
      Fork([&] {
        edsp::cia402::ShmDriveServerOptions options;
        options.prefix = prefix;
        return std::make_unique<edsp::cia402::CspShmServer>(options);
      });
      return;
    }
    edsp::cia402::DriveServerOptions options;
    options.port = 0;
    auto server = std::make_shared<edsp::cia402::ModbusDriveServer>(options);
    port = server->port();
    Fork([server] { return server; });
  }
  // Runs the server `make` returns in a child process.
  template <typename Make>
  void Fork(Make make) {
    const pid_t parent = ::getpid();
    pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlives the benchmark
      make()->Run([parent] { return ::getppid() != parent; });
      ::_exit(0);
    }
  }
  ~ChildServer() {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    if (!segment.empty()) edsp::RemoveSegment(segment);
  }
  ChildServer(const ChildServer&) = delete;
  ChildServer& operator=(const ChildServer&) = delete;
};

// "HOST:PORT" as given to --connect; throws naming the text.
std::pair<std::string, int> Endpoint(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  int port = 0;
  try {
    if (colon != std::string::npos) port = std::stoi(text.substr(colon + 1));
  } catch (const std::exception&) {
    port = 0;
  }
  if (colon == std::string::npos || colon == 0 || port < 1 || port > 65535) {
    throw std::runtime_error("--connect " + text + ": expected HOST:PORT with a port in [1, 65535]");
  }
  return {text.substr(0, colon), port};
}

struct Options {
  int cycles = 20000, warmup = 500;
  double period_us = 1000.0;
  bool json = false;
  std::string connect;
  std::string link = "modbus";
};

// Connected to the server; one elsewhere may still be starting: tried for 5 s.
void ConnectMaster(edsp::cia402::CspLink* master, bool remote) {
  std::string error;
  const auto give_up = Clock::now() + std::chrono::seconds(remote ? 5 : 0);
  while (!master->Connect(&error)) {
    if (Clock::now() >= give_up) throw std::runtime_error(error);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

struct CycleTimes {
  std::vector<double> exchange_us;  // the timed cycles' read+write
  int failures = 0;
};

// Warm-up cycles enable the drives through the CiA 402 state machine; the
// timed ones ramp the target, paced at the period.
CycleTimes RunCycles(edsp::cia402::CspLink* master, const Options& o) {
  CycleTimes out;
  out.exchange_us.reserve(static_cast<std::size_t>(o.cycles));
  CspCommands commands{};
  CspFeedbacks feedback{};
  std::string error;
  const auto period = std::chrono::microseconds(static_cast<long>(o.period_us));
  auto next = Clock::now();
  std::int32_t target = 0;
  for (int k = 0; k < o.warmup + o.cycles; ++k) {
    if (k >= o.warmup) target += 100;  // a ramp once enabled
    for (std::size_t d = 0; d < commands.size(); ++d) {
      commands[d] = edsp::cia402::NextCspCommand(feedback[d], commands[d].controlword, target);
    }
    const auto start = Clock::now();
    if (!master->Exchange(commands, &feedback, &error)) {
      ++out.failures;
      if (!master->Connect(&error)) break;
      continue;
    }
    if (k >= o.warmup)
      out.exchange_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    next += period;
    if (period.count() > 0) std::this_thread::sleep_until(next);
  }
  return out;
}

void PrintText(const nlohmann::json& report, std::size_t cycles, int failures) {
  const auto& e = report["exchange"];
  const auto& t = report["timer_baseline_late"];
  std::printf(
      "%s cycle (6 drives, 1 exchange): p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us "
      "(%zu cycles, %d failed)\n",
      report["link"].get<std::string>().c_str(), e["p50_us"].get<double>(), e["p99_us"].get<double>(),
      e["p999_us"].get<double>(), e["max_us"].get<double>(), cycles, failures);
  std::printf("timer baseline (1 ms sleep, late by): p50 %.1f us, p99 %.1f us, max %.1f us\n",
              t["p50_us"].get<double>(), t["p99_us"].get<double>(), t["max_us"].get<double>());
}

int Run(int argc, char** argv) {
  Options o;
  CLI::App app{"One cycle of six CiA 402 drives over Modbus TCP or the shared-memory image: read+write time"};
  app.add_option("--cycles", o.cycles, "timed cycles")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--warmup", o.warmup, "untimed cycles first (enable the drives)")->capture_default_str();
  app.add_option("--period-us", o.period_us, "pace of the master's cycles")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100000.0));
  app.add_flag("--json", o.json, "one JSON object on stdout");
  app.add_option("--connect", o.connect,
                 "HOST:PORT of a server elsewhere, waited for up to 5 s (default: a child on loopback)");
  app.add_option("--link", o.link, "modbus: Modbus TCP; shm: the CSP image in shared memory (a child server)")
      ->capture_default_str()
      ->check(CLI::IsMember({"modbus", "shm"}));
  CLI11_PARSE(app, argc, argv);
  const bool shm = o.link == "shm";
  if (shm && !o.connect.empty()) throw std::runtime_error("--connect: only with --link modbus (shm is this host's)");

  std::unique_ptr<ChildServer> child;
  std::pair<std::string, int> endpoint;
  const std::string prefix = fmt::format("edsp.bench.{}", ::getpid());
  if (o.connect.empty()) {
    child = std::make_unique<ChildServer>(shm, prefix);
    endpoint = {"127.0.0.1", child->port};
  } else {
    endpoint = Endpoint(o.connect);
  }
  std::unique_ptr<edsp::cia402::CspLink> master;
  if (shm)
    master = std::make_unique<edsp::cia402::CspShmMaster>(prefix, 0600, 0.5);
  else
    master = std::make_unique<edsp::cia402::ModbusDriveMaster>(endpoint.first, endpoint.second, 0.5);
  ConnectMaster(master.get(), !o.connect.empty() || shm);
  const CycleTimes cycles = RunCycles(master.get(), o);
  const std::vector<double> timer = SleepLateness(std::chrono::microseconds(1000), 2000);

  const nlohmann::json report = {
      {"drives", 6},
      {"link", master->endpoint().substr(0, master->endpoint().find(' '))},
      {"server", shm ? master->endpoint() : fmt::format("{}:{}", endpoint.first, endpoint.second)},
      {"registers_per_cycle", shm ? 0 : 2 * edsp::cia402::modbus_map::kBlockRegisters},
      {"period_us", o.period_us},
      {"failures", cycles.failures},
      {"exchange", Summary(cycles.exchange_us)},
      {"timer_baseline_late", Summary(timer)}};
  if (o.json)
    std::printf("%s\n", report.dump().c_str());
  else
    PrintText(report, cycles.exchange_us.size(), cycles.failures);
  return cycles.failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-bench-drives: error: %s\n", e.what());
    return 1;
  }
}
