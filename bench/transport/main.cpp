// edsp-bench-transport: two-process ping-pong round-trip times and CPU use
// for edsp's shared memory (spin, blocking, spin-then-block), LCM udpm and Eclipse iceoryx
// (polling, WaitSet), plus one-way shared-memory throughput at 64 KiB.
// Every pair runs as two fresh child processes; the parent only orchestrates,
// so CPU seconds are exactly the two children's. Runs inside a private
// network namespace it creates (no packet leaves the machine).
//
//   edsp-bench-transport [--json] [--round-trips 20000] [--warmup 1000]
//                        [--payloads 64,4096,65536] [--transports shm-spin,...]
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/transport/private_network.h"
#include "edsp/transport/shm_channel.h"
#include "endpoint.h"

namespace edsp::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::uint64_t kStop = ~0ull;

// ---- plumbing between the parent and its two children ----------------------

struct Pipe {
  int fd[2] = {-1, -1};
  Pipe() { (void)!::pipe(fd); }
  ~Pipe() {
    ::close(fd[0]);
    ::close(fd[1]);
  }
  void Write(const void* data, std::size_t size) {
    const auto* p = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t n = ::write(fd[1], p, size);
      if (n <= 0) return;
      p += n;
      size -= static_cast<std::size_t>(n);
    }
  }
  bool Read(void* data, std::size_t size, int timeout_ms) {
    auto* p = static_cast<char*>(data);
    while (size > 0) {
      pollfd pfd{fd[0], POLLIN, 0};
      if (::poll(&pfd, 1, timeout_ms) != 1) return false;
      const ssize_t n = ::read(fd[0], p, size);
      if (n <= 0) return false;
      p += n;
      size -= static_cast<std::size_t>(n);
    }
    return true;
  }
};

template <typename Body>
pid_t Spawn(Body&& body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    int rc = 1;
    try {
      rc = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "edsp-bench-transport: child: %s\n", e.what());
    }
    // exit(), not _exit(): iceoryx's runtime must deregister from RouDi in its
    // static destructor, or RouDi aborts at shutdown and leaves its segments.
    std::exit(rc);
  }
  return pid;
}

double ReapCpuSeconds(pid_t pid, int* exit_code) {
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// ---- one ping-pong run -------------------------------------------------------

std::unique_ptr<Endpoint> MakeEndpoint(const std::string& transport, const Roles& roles, std::uint32_t payload) {
  if (transport == "shm-spin") return MakeShmEndpoint(roles, payload, ShmWait::kSpin);
  if (transport == "shm-block") return MakeShmEndpoint(roles, payload, ShmWait::kBlock);
  if (transport == "shm-hybrid") return MakeShmEndpoint(roles, payload, ShmWait::kHybrid);
  if (transport == "lcm-udpm") return MakeLcmEndpoint(roles);
  if (transport == "iceoryx-spin") return MakeIceoryxEndpoint(roles, payload, false);
  if (transport == "iceoryx-waitset") return MakeIceoryxEndpoint(roles, payload, true);
  throw std::runtime_error("unknown transport " + transport);
}

struct RunResult {
  std::vector<double> rtt_us;
  double cpu_s = 0.0;
  std::string error;
};

int Pinger(const std::string& transport, const Roles& roles, std::uint32_t payload, int warmup, int round_trips,
           Pipe& peer_ready, Pipe& results) {
  auto endpoint = MakeEndpoint(transport, roles, payload);
  char ready = 0;
  if (!peer_ready.Read(&ready, 1, 20000)) return 3;
  endpoint->WaitForPeer();
  std::vector<std::uint8_t> out(payload, 0x5a), in(payload, 0);
  std::vector<double> rtt;
  rtt.reserve(static_cast<std::size_t>(round_trips));
  for (int i = 0; i < warmup + round_trips; ++i) {
    const std::uint64_t counter = static_cast<std::uint64_t>(i);
    std::memcpy(out.data(), &counter, sizeof counter);
    const auto start = Clock::now();
    if (!endpoint->Send(out.data(), payload) ||
        !endpoint->Receive(in.data(), payload, std::chrono::milliseconds(2000))) {
      return 4;
    }
    const auto stop = Clock::now();
    std::uint64_t echo = 0;
    std::memcpy(&echo, in.data(), sizeof echo);
    if (echo != counter) return 5;
    if (i >= warmup) rtt.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
  }
  std::memcpy(out.data(), &kStop, sizeof kStop);
  endpoint->Send(out.data(), payload);
  const std::uint64_t count = rtt.size();
  results.Write(&count, sizeof count);
  results.Write(rtt.data(), rtt.size() * sizeof(double));
  return 0;
}

int Ponger(const std::string& transport, const Roles& roles, std::uint32_t payload, Pipe& ready) {
  auto endpoint = MakeEndpoint(transport, roles, payload);
  endpoint->WaitForPeer();
  ready.Write("r", 1);
  std::vector<std::uint8_t> buffer(payload, 0);
  while (endpoint->Receive(buffer.data(), payload, std::chrono::milliseconds(10000))) {
    std::uint64_t counter = 0;
    std::memcpy(&counter, buffer.data(), sizeof counter);
    if (counter == kStop) return 0;
    endpoint->Send(buffer.data(), payload);
  }
  return 6;
}

RunResult RunPingPong(const std::string& transport, std::uint32_t payload, int warmup, int round_trips,
                      int run_number) {
  const Roles ping{"PING", "PONG", fmt::format("edsp.bench.{}.{}", ::getpid(), run_number)};
  const Roles pong{"PONG", "PING", ping.run_id};
  Pipe ready, results;
  const pid_t ponger = Spawn([&] { return Ponger(transport, pong, payload, ready); });
  const pid_t pinger = Spawn([&] { return Pinger(transport, ping, payload, warmup, round_trips, ready, results); });
  RunResult result;
  std::uint64_t count = 0;
  if (results.Read(&count, sizeof count, 600000) && count == static_cast<std::uint64_t>(round_trips)) {
    result.rtt_us.resize(count);
    results.Read(result.rtt_us.data(), count * sizeof(double), 60000);
  }
  int pinger_exit = 0, ponger_exit = 0;
  result.cpu_s = ReapCpuSeconds(pinger, &pinger_exit) + ReapCpuSeconds(ponger, &ponger_exit);
  if (pinger_exit != 0 || ponger_exit != 0 || result.rtt_us.empty()) {
    result.error = fmt::format("pinger exit {}, ponger exit {}", pinger_exit, ponger_exit);
    result.rtt_us.clear();
  }
  return result;
}

// ---- one-way throughput ------------------------------------------------------

struct Throughput {
  double gb_per_s = 0.0;
  std::uint64_t received = 0;
  std::uint64_t overruns = 0;
  double seconds = 0.0;
};

Throughput RunShmThroughput(std::uint32_t payload, double seconds) {
  ShmChannelSpec spec{fmt::format("edsp.bench.{}.throughput", ::getpid()), 0x7468726f75676870, 64, payload, 0600};
  Pipe ready, results;
  const pid_t writer = Spawn([&] {
    auto w = ShmWriter::Open(spec);
    if (!w.ok()) return 2;
    std::vector<std::uint8_t> source(payload, 0xa5);
    char go = 0;
    if (!ready.Read(&go, 1, 20000)) return 3;
    const auto until = Clock::now() + std::chrono::duration<double>(seconds + 0.2);
    while (Clock::now() < until) {
      for (int k = 0; k < 64; ++k) {
        w.value->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
          std::memcpy(buffer, source.data(), payload);
          return payload;
        });
      }
    }
    return 0;
  });
  std::unique_ptr<ShmReader> reader;
  for (int k = 0; k < 5000 && reader == nullptr; ++k) {
    auto r = ShmReader::Open(spec);
    if (r.ok())
      reader = std::move(r.value);
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  Throughput t;
  if (reader == nullptr) return t;
  std::vector<std::uint8_t> sink(payload);
  ready.Write("g", 1);
  reader->Wait(std::chrono::seconds(5));
  const auto start = Clock::now();
  const auto until = start + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    reader->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
      std::memcpy(sink.data(), data, size);
      return true;
    });
  }
  t.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  t.received = reader->stats().received;
  t.overruns = reader->stats().overruns;
  t.gb_per_s = static_cast<double>(t.received) * payload / t.seconds / 1e9;
  int exit_code = 0;
  ReapCpuSeconds(writer, &exit_code);
  return t;
}

// ---- RouDi, statistics, output -------------------------------------------------

pid_t StartRouDi() {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::freopen("/dev/null", "w", stdout);
    ::freopen("/dev/null", "w", stderr);
    ::execlp("iox-roudi", "iox-roudi", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  int status = 0;
  if (::waitpid(pid, &status, WNOHANG) == pid) return -1;  // did not start
  return pid;
}

void StopRouDi(pid_t pid) {
  if (pid <= 0) return;
  ::kill(pid, SIGINT);
  for (int k = 0; k < 50; ++k) {
    if (::waitpid(pid, nullptr, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
}

double Percentile(const std::vector<double>& sorted, double q) {
  const auto index = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5);
  return sorted[std::min(index, sorted.size() - 1)];
}

nlohmann::json Summary(std::vector<double> rtt) {
  std::sort(rtt.begin(), rtt.end());
  return {{"min", rtt.front()},
          {"p50", Percentile(rtt, 0.50)},
          {"p99", Percentile(rtt, 0.99)},
          {"p999", Percentile(rtt, 0.999)},
          {"max", rtt.back()}};
}

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

double P50(const nlohmann::json& results, const std::string& transport, int payload) {
  for (const auto& r : results) {
    if (r["transport"] == transport && r["payload_bytes"] == payload && r.contains("rtt_us")) {
      return r["rtt_us"]["p50"].get<double>();
    }
  }
  return 0.0;
}

void PrintTable(const nlohmann::json& out) {
  std::printf("%-16s %8s %9s %9s %9s %9s %10s %8s\n", "transport", "payload", "min_us", "p50_us", "p99_us", "p999_us",
              "max_us", "cpu_s");
  for (const auto& r : out["results"]) {
    if (r.contains("error")) {
      std::printf("%-16s %8d  error: %s\n", r["transport"].get<std::string>().c_str(), r["payload_bytes"].get<int>(),
                  r["error"].get<std::string>().c_str());
      continue;
    }
    const auto& t = r["rtt_us"];
    std::printf("%-16s %8d %9.2f %9.2f %9.2f %9.2f %10.1f %8.2f\n", r["transport"].get<std::string>().c_str(),
                r["payload_bytes"].get<int>(), t["min"].get<double>(), t["p50"].get<double>(), t["p99"].get<double>(),
                t["p999"].get<double>(), t["max"].get<double>(), r["cpu_s"].get<double>());
  }
  std::printf("\nshm one-way throughput at 64 KiB: %.2f GB/s\n", out["throughput_GBps_64KiB"].get<double>());
  for (auto it = out["ratios_p50_64B"].begin(); it != out["ratios_p50_64B"].end(); ++it) {
    std::printf("%s: %.2f\n", it.key().c_str(), it.value().get<double>());
  }
}

struct Options {
  bool json = false;
  int round_trips = 20000, warmup = 1000;
  double throughput_seconds = 1.0;
  std::vector<std::uint32_t> payloads;
  std::vector<std::string> transports;
};

bool IsIceoryx(const std::string& transport) { return transport.rfind("iceoryx", 0) == 0; }

// Payload sizes from "64,4096,…"; false (and the error said) for a size out of 8..1 MiB.
bool ParsePayloads(const std::string& text, std::vector<std::uint32_t>* payloads) {
  for (const std::string& p : Split(text)) {
    char* end = nullptr;
    const unsigned long value = std::strtoul(p.c_str(), &end, 10);
    if (p.empty() || *end != '\0' || value < 8 || value > (1u << 20)) {
      std::fprintf(stderr, "edsp-bench-transport: error: --payloads: \"%s\" must be 8..1048576\n", p.c_str());
      return false;
    }
    payloads->push_back(static_cast<std::uint32_t>(value));
  }
  return true;
}

bool ParseTransports(const std::string& text, std::vector<std::string>* transports) {
  static const std::vector<std::string> kKnown = {"shm-spin", "shm-block",    "shm-hybrid",
                                                  "lcm-udpm", "iceoryx-spin", "iceoryx-waitset"};
  *transports = Split(text);
  for (const std::string& t : *transports) {
    if (std::find(kKnown.begin(), kKnown.end(), t) == kKnown.end()) {
      std::fprintf(stderr, "edsp-bench-transport: error: --transports: unknown \"%s\"\n", t.c_str());
      return false;
    }
  }
  return true;
}

// Every transport × payload ping-pong, iox-roudi started for the iceoryx ones.
nlohmann::json RunPingPongs(const Options& o) {
  const bool iceoryx = std::any_of(o.transports.begin(), o.transports.end(), IsIceoryx);
  const pid_t roudi = iceoryx ? StartRouDi() : 0;
  nlohmann::json results = nlohmann::json::array();
  int run = 0;
  for (const std::string& transport : o.transports) {
    for (std::uint32_t payload : o.payloads) {
      nlohmann::json r{{"transport", transport}, {"payload_bytes", payload}, {"round_trips", o.round_trips}};
      if (IsIceoryx(transport) && roudi <= 0) {
        r["error"] = "iox-roudi could not be started";
      } else {
        const RunResult result = RunPingPong(transport, payload, o.warmup, o.round_trips, run++);
        if (result.error.empty()) {
          r["rtt_us"] = Summary(result.rtt_us);
          r["cpu_s"] = result.cpu_s;
          r["cpu_us_per_round_trip"] = result.cpu_s * 1e6 / (o.round_trips + o.warmup);
        } else {
          r["error"] = result.error;
        }
      }
      if (!o.json) std::fprintf(stderr, "%s %u done\n", transport.c_str(), payload);
      results.push_back(r);
    }
  }
  StopRouDi(roudi);
  return results;
}

// The shm throughput at 64 KiB and the 64 B latency ratios, measured in this run.
void AddThroughputAndRatios(const Options& o, nlohmann::json* out) {
  const Throughput t = RunShmThroughput(65536, o.throughput_seconds);
  (*out)["throughput_GBps_64KiB"] = t.gb_per_s;
  (*out)["throughput_64KiB"] = {{"received", t.received}, {"overruns", t.overruns}, {"seconds", t.seconds}};
  const nlohmann::json& results = (*out)["results"];
  auto ratio = [&](const char* a, const char* b) {
    const double pb = P50(results, b, 64);
    return pb > 0.0 ? P50(results, a, 64) / pb : 0.0;
  };
  (*out)["ratios_p50_64B"] = {{"shm-spin/iceoryx-spin", ratio("shm-spin", "iceoryx-spin")},
                              {"shm-block/iceoryx-waitset", ratio("shm-block", "iceoryx-waitset")},
                              {"lcm-udpm/shm-spin", ratio("lcm-udpm", "shm-spin")},
                              {"lcm-udpm/shm-block", ratio("lcm-udpm", "shm-block")},
                              {"lcm-udpm/shm-hybrid", ratio("lcm-udpm", "shm-hybrid")}};
}

bool AnyRunFailed(const nlohmann::json& out) {
  const nlohmann::json& results = out["results"];
  return std::any_of(results.begin(), results.end(), [](const nlohmann::json& r) { return r.contains("error"); });
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-bench-transport: shm vs LCM vs iceoryx ping-pong and throughput"};
  Options o;
  std::string payloads_text = "64,4096,65536";
  std::string transports_text = "shm-spin,shm-block,shm-hybrid,lcm-udpm,iceoryx-spin,iceoryx-waitset";
  app.add_flag("--json", o.json, "print JSON");
  app.add_option("--round-trips", o.round_trips, "measured round trips per run")->check(CLI::Range(10, 10000000));
  app.add_option("--warmup", o.warmup, "round trips before measuring")->check(CLI::Range(0, 1000000));
  app.add_option("--payloads", payloads_text, "payload sizes in bytes, comma-separated");
  app.add_option("--transports", transports_text, "comma-separated subset");
  app.add_option("--throughput-seconds", o.throughput_seconds)->check(CLI::Range(0.1, 60.0));
  CLI11_PARSE(app, argc, argv);
  if (!ParsePayloads(payloads_text, &o.payloads) || !ParseTransports(transports_text, &o.transports)) return 2;
  try {
    edsp::EnterPrivateNetworkNamespace();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-bench-transport: error: %s\n", e.what());
    return 1;
  }
  nlohmann::json out;
  out["results"] = RunPingPongs(o);
  AddThroughputAndRatios(o, &out);
  out["machine"] = {{"cpus", std::thread::hardware_concurrency()}};
  if (o.json)
    std::printf("%s\n", out.dump(2).c_str());
  else
    PrintTable(out);
  return AnyRunFailed(out) ? 1 : 0;
}

}  // namespace
}  // namespace edsp::bench

int main(int argc, char** argv) { return edsp::bench::Run(argc, argv); }
