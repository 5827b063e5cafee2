#include "virtual_network.h"

#include <dirent.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

namespace edsp::test_support {

namespace {

constexpr const char* kPrefix = "edspmh";

int Shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void Must(const std::string& command) {
  if (Shell(command + " 2>/tmp/edsp_multihost_step.err") != 0) {
    throw std::runtime_error("virtual network: `" + command + "` failed (see /tmp/edsp_multihost_step.err)");
  }
}

std::string Capture(const std::string& command) {
  std::string out;
  if (FILE* p = ::popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) out.append(buffer, n);
    ::pclose(p);
  }
  return out;
}

void DeleteNamespace(const std::string& ns) {
  Shell(fmt::format("ip netns pids {0} 2>/dev/null | xargs -r kill -9 2>/dev/null; ip netns del {0} 2>/dev/null", ns));
}

// Namespaces of test runs that died without their destructor.
void RemoveLeftovers() {
  const std::regex name(std::string("^") + kPrefix + "([0-9]+)-");
  std::string listing = Capture("ip netns list 2>/dev/null");
  std::size_t at = 0;
  while (at < listing.size()) {
    const std::size_t end = std::min(listing.find('\n', at), listing.size());
    const std::string ns = listing.substr(at, listing.find(' ', at) < end ? listing.find(' ', at) - at : end - at);
    std::smatch m;
    if (std::regex_search(ns, m, name) && ::kill(std::stoi(m[1]), 0) != 0) DeleteNamespace(ns);
    at = end + 1;
  }
}

}  // namespace

VirtualNetwork::VirtualNetwork(const std::vector<std::string>& hosts)
    : prefix_(fmt::format("{}{}-", kPrefix, ::getpid())), hosts_(hosts) {
  RemoveLeftovers();
  const std::string sw = prefix_ + "switch";
  try {
    Must("ip netns add " + sw);
    Must(fmt::format("ip -n {} link add br0 type bridge mcast_snooping 0", sw));
    Must(fmt::format("ip -n {} link set br0 up", sw));
    for (std::size_t i = 0; i < hosts_.size(); ++i) {
      const std::string ns = Namespace(hosts_[i]);
      const std::string port = SwitchPort(static_cast<int>(i));
      Must("ip netns add " + ns);
      Must(fmt::format("ip -n {} link set lo up", ns));
      Must(fmt::format("ip -n {} link add eth0 type veth peer name {} netns {}", ns, port, sw));
      Must(fmt::format("ip -n {} link set {} master br0 up", sw, port));
      Must(fmt::format("ip -n {} addr add {}/24 dev eth0", ns, Address(hosts_[i])));
      Must(fmt::format("ip -n {} link set eth0 up", ns));
      Must(fmt::format("ip -n {} route add 224.0.0.0/4 dev eth0", ns));
    }
  } catch (...) {
    TearDown();
    throw;
  }
}

VirtualNetwork::~VirtualNetwork() { TearDown(); }

void VirtualNetwork::TearDown() const {
  for (const std::string& host : hosts_) DeleteNamespace(Namespace(host));
  DeleteNamespace(prefix_ + "switch");
}

std::string VirtualNetwork::Namespace(const std::string& host) const { return prefix_ + host; }

std::string VirtualNetwork::Address(const std::string& host) const {
  return fmt::format("10.77.0.{}", IndexOf(host) + 1);
}

int VirtualNetwork::IndexOf(const std::string& host) const {
  for (std::size_t i = 0; i < hosts_.size(); ++i) {
    if (hosts_[i] == host) return static_cast<int>(i);
  }
  throw std::runtime_error("virtual network: no host " + host);
}

std::string VirtualNetwork::SwitchPort(int index) const {
  return fmt::format("mh{}p{}", ::getpid() % 100000, index);  // ≤ 15 characters
}

pid_t VirtualNetwork::Spawn(const std::string& host, const std::string& command, const std::string& log_file) const {
  // `ip netns exec` gives the command a mount namespace of its own, where a
  // fresh tmpfs on /dev/shm is this host's alone.
  const std::string line =
      fmt::format("exec ip netns exec {} sh -c 'mount -t tmpfs -o size=512m tmpfs /dev/shm && exec {}' >{} 2>&1",
                  Namespace(host), command, log_file);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  if (pid < 0) throw std::runtime_error("virtual network: fork failed");
  return pid;
}

int VirtualNetwork::Run(const std::string& host, const std::string& command) const {
  return Shell(fmt::format("ip netns exec {} sh -c '{}'", Namespace(host), command));
}

int VirtualNetwork::Wait(pid_t pid, int timeout_ms) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -1;
}

int VirtualNetwork::Stop(pid_t pid, int grace_ms) {
  ::kill(-pid, SIGINT);
  return Wait(pid, grace_ms);
}

void VirtualNetwork::SetLink(const std::string& host, bool up) const {
  Must(fmt::format("ip -n {}switch link set {} {}", prefix_, SwitchPort(IndexOf(host)), up ? "up" : "down"));
}

void VirtualNetwork::DropRandomly(const std::string& host, double fraction) const {
  const std::string ns = Namespace(host);
  Shell(fmt::format("ip netns exec {} nft delete table inet edsp_loss 2>/dev/null", ns));
  if (fraction <= 0.0) return;
  const int per_10000 = static_cast<int>(fraction * 10000.0 + 0.5);
  const std::string rules = fmt::format("/tmp/{}loss.nft", prefix_);
  std::ofstream(rules) << fmt::format(
      "table inet edsp_loss {{\n"
      "  chain in {{\n    type filter hook input priority 0; policy accept;\n"
      "    meta l4proto udp numgen random mod 10000 < {0} counter drop\n  }}\n"
      "  chain out {{\n    type filter hook output priority 0; policy accept;\n"
      "    meta l4proto udp numgen random mod 10000 < {0} counter drop\n  }}\n"
      "}}\n",
      per_10000);
  Must(fmt::format("ip netns exec {} nft -f {}", ns, rules));
  std::remove(rules.c_str());
}

void VirtualNetwork::BlockTcpPort(const std::string& host, int port, bool blocked) const {
  const std::string ns = Namespace(host);
  const std::string table = fmt::format("edsp_block_{}", port);
  Shell(fmt::format("ip netns exec {} nft delete table inet {} 2>/dev/null", ns, table));
  if (!blocked) return;
  const std::string rules = fmt::format("/tmp/{}{}.nft", prefix_, table);
  std::ofstream(rules) << fmt::format(
      "table inet {0} {{\n"
      "  chain in {{\n    type filter hook input priority 0; policy accept;\n"
      "    tcp dport {1} drop\n    tcp sport {1} drop\n  }}\n"
      "  chain out {{\n    type filter hook output priority 0; policy accept;\n"
      "    tcp dport {1} drop\n    tcp sport {1} drop\n  }}\n"
      "}}\n",
      table, port);
  Must(fmt::format("ip netns exec {} nft -f {}", ns, rules));
  std::remove(rules.c_str());
}

long VirtualNetwork::DroppedPackets(const std::string& host) const {
  const std::string listing =
      Capture(fmt::format("ip netns exec {} nft list table inet edsp_loss 2>/dev/null", Namespace(host)));
  long total = 0;
  const std::regex counter("counter packets ([0-9]+)");
  for (auto it = std::sregex_iterator(listing.begin(), listing.end(), counter); it != std::sregex_iterator(); ++it) {
    total += std::stol((*it)[1]);
  }
  return total;
}

}  // namespace edsp::test_support
