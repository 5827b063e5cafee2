#pragma once
// A running group's LCM traffic seen from the test process, so that a test
// acts on what the group does (the platform moving, a restarted member
// publishing again) rather than on a sleep tuned to one machine's start-up:
// a sanitized node on a busy two-core machine starts several times slower.
// Its listener runs at a real-time priority below the nodes' when it may:
// it takes every datagram of the group (some 5 000 a second), and starved
// by other work on a busy machine its socket's backlog grows to seconds, so
// a test would act on the platform's motion seconds after it happened (a
// fault meant for mid-motion would land in a hold).

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "edsp/fault_t.hpp"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp::test_support {

class GroupWatch {
 public:
  // Listens to EDSP_SETPOINT, EDSP_FAULT, EDSP_RIG_TRUTH and every channel
  // named in `channels` (a regex, as lcm::LCM::subscribe takes it; one that
  // matches those three too hands their messages over twice, which no
  // count here minds) on `lcm_url` until destroyed.
  GroupWatch(const std::string& lcm_url, const std::string& channels);
  ~GroupWatch();
  GroupWatch(const GroupWatch&) = delete;
  GroupWatch& operator=(const GroupWatch&) = delete;

  bool ok() const { return lcm_.good(); }

  // How far behind the group this watch reads: when the newest setpoint
  // arrived here minus when the planner stamped it (µs).
  std::int64_t SetpointLagUs();
  // Waits until the newest setpoint satisfies `reached`; false on timeout.
  bool WaitForSetpoint(const std::function<bool(const pose_setpoint_t&)>& reached, std::chrono::milliseconds timeout);
  // Waits until a message on `channel` arrives at or after `after_utime`
  // (this process's clock, UtimeNow); false on timeout.
  bool WaitForMessage(const std::string& channel, std::int64_t after_utime, std::chrono::milliseconds timeout);
  // How often a new publisher took `channel` over so far: its seq started
  // again below the last one seen (a restarted member counts from 1).
  int Restarts(const std::string& channel);
  // Waits until Restarts(channel) exceeds `seen`; false on timeout.
  bool WaitForRestart(const std::string& channel, int seen, std::chrono::milliseconds timeout);
  // When the bridge last said it holds until re-armed (a latch, or a
  // command refused for it, which it repeats every 100 ms while latched),
  // on this process's clock; 0: never.
  std::int64_t LastReArmRequestUtime();
  // Waits until the rig's true platform position (EDSP_RIG_TRUTH) has
  // stayed within 1 µm for `still_for`, all of it seen at or after
  // `after_utime`; false on timeout. The fault tests re-arm only then: a
  // re-arm before the hold has settled would cut the hold they measure.
  bool WaitForRest(std::int64_t after_utime, std::chrono::milliseconds still_for, std::chrono::milliseconds timeout);
  // Waits until `node` has said something containing `text` on EDSP_FAULT,
  // stamped at or after `after_utime`; false on timeout.
  bool WaitForFault(const std::string& node, const std::string& text, std::int64_t after_utime,
                    std::chrono::milliseconds timeout);

 private:
  static void OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel, GroupWatch* self);
  void Listen();
  void TrackRest(const double (&pose)[6], std::int64_t now);  // under mutex_

  lcm::LCM lcm_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, std::int64_t> last_received_utime_;
  std::map<std::string, std::int64_t> last_seq_;
  std::map<std::string, int> restarts_;
  std::int64_t last_rearm_request_utime_ = 0;
  std::vector<fault_t> faults_;
  // The platform's true position, where it last moved by more than 1 µm
  // (and when), and when the newest truth came.
  std::array<double, 3> rest_anchor_{};
  std::int64_t rest_anchor_utime_ = 0;
  std::int64_t last_truth_utime_ = 0;
  pose_setpoint_t setpoint_{};
  std::int64_t setpoint_lag_us_ = 0;
  bool have_setpoint_ = false;
  bool stop_ = false;
  std::thread listener_;
};

// While the group's setpoints flow, re-arms the bridge (with `arm`) each
// time it says it holds until re-armed, 300 ms or more after the last arm
// (refusals already in flight then do not count): a machine stall later in
// a run may latch it, which the caller then asks a stall to explain
// (late_cycles.h). Returns how many times it re-armed.
int ReArmWhileLatched(GroupWatch* watch, const std::function<void()>& arm);

}  // namespace edsp::test_support
