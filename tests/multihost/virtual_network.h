#pragma once
// A network of "hosts" on this one machine for the multi-host tests: one
// network namespace per host, each with eth0 (a veth) on a bridge that lives
// in a switch namespace of its own, 224.0.0.0/4 routed over eth0, and a
// private /dev/shm per host (shared memory must not reach across hosts).
// Nothing is attached to the machine's own network. Torn down in the
// destructor, whatever the test did; namespaces left by a killed test run
// are removed by the next one.

#include <sys/types.h>

#include <string>
#include <vector>

namespace edsp::test_support {

class VirtualNetwork {
 public:
  // Host i gets 10.77.0.(i+1)/24. Throws std::runtime_error naming the step that failed.
  explicit VirtualNetwork(const std::vector<std::string>& hosts);
  ~VirtualNetwork();
  VirtualNetwork(const VirtualNetwork&) = delete;
  VirtualNetwork& operator=(const VirtualNetwork&) = delete;

  // Runs `command` (sh) on `host`, stdout and stderr to `log_file`; returns
  // its pid (a process group of its own). The command gets a fresh /dev/shm.
  pid_t Spawn(const std::string& host, const std::string& command, const std::string& log_file) const;
  // Runs `command` on `host` to its end; returns its exit status (-1: signal).
  int Run(const std::string& host, const std::string& command) const;
  // SIGINT to a spawned process group, then SIGKILL after `grace_ms`;
  // returns its exit status (-1: killed).
  static int Stop(pid_t pid, int grace_ms = 8000);
  // Waits for a spawned process; returns its exit status (-1: killed or timed out and killed).
  static int Wait(pid_t pid, int timeout_ms);

  // The host's cable: its port on the switch goes down (its eth0 loses carrier) or up.
  void SetLink(const std::string& host, bool up) const;
  // nftables on the host drops this fraction of its UDP packets, in and out,
  // at random (numgen random); 0 removes the rule. DroppedPackets() reads its counters.
  void DropRandomly(const std::string& host, double fraction) const;
  long DroppedPackets(const std::string& host) const;
  // nftables on the host drops every TCP segment to or from `port`, in and
  // out (a pulled cable for that one connection: the host's LCM traffic
  // still flows), or removes that rule.
  void BlockTcpPort(const std::string& host, int port, bool blocked) const;

  std::string Namespace(const std::string& host) const;
  std::string Address(const std::string& host) const;

 private:
  int IndexOf(const std::string& host) const;
  void TearDown() const;
  std::string SwitchPort(int index) const;

  std::string prefix_;
  std::vector<std::string> hosts_;
};

}  // namespace edsp::test_support
