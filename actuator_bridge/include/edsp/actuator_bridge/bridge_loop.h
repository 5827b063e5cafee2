#pragma once
// The actuator bridge on a bus: EDSP_LEG_COMMAND and EDSP_ARM in,
// EDSP_LEG_STATE, EDSP_REPLY, EDSP_FAULT and EDSP_STATUS out, and the drive cycle on a
// clock (the bridge's own, or one its backend owns). The process's main only
// parses options, builds the backend and runs this; tests run it on an
// in-process bus with a clock of their own.

#include <chrono>
#include <cstdint>
#include <functional>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/node/latency_recorder.h"
#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

// The bridge's default cycle: 1 kHz, 400 µs after the planner's tick on the
// host's grid, so a command that crossed the kinematics in time is written
// in the cycle it was planned for (docs/drives.md: the cycle).
inline constexpr std::chrono::microseconds kBridgePeriod{1000};
inline constexpr std::chrono::microseconds kBridgePhase{400};

class BridgeLoop {
 public:
  // Set-up: subscribes and advertises on `bus` (may throw TransportError).
  // The bus and the bridge must outlive the loop.
  BridgeLoop(Bus& bus, ActuatorBridge& bridge);
  // The bus's handlers point at this loop: no copy, no move, and no
  // Bus::Handle after it is gone.
  BridgeLoop(const BridgeLoop&) = delete;
  BridgeLoop& operator=(const BridgeLoop&) = delete;

  // Until stop() is true: input until the clock's next tick, then a cycle.
  void Run(CycleClock& clock, const std::function<bool()>& stop);
  // One drive cycle at now: ActuatorBridge::Cycle, EDSP_LEG_STATE, faults,
  // the state on EDSP_STATUS.
  void RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);

  // Setpoint utime → the bridge accepting its command (the transport's share).
  const LatencyRecorder& arrival_latency() const { return arrival_; }
  // Setpoint utime → the start of the cycle that wrote it to the drives.
  const LatencyRecorder& write_latency() const { return written_; }
  const ChannelCounters& commands_in() const { return commands_in_; }

 private:
  void OnCommand(const leg_command_t& command);
  void OnArm(const arm_t& arm);

  Bus& bus_;
  ActuatorBridge& bridge_;
  Bus::Publisher<leg_state_t> states_;
  Bus::Publisher<reply_t> replies_;
  NodeReporting reporting_;
  const ChannelCounters& commands_in_;  // node-based map: no lookup per cycle
  LatencyRecorder arrival_, written_;
  std::int64_t last_written_setpoint_utime_ = 0;
};

// The report --latency-report writes: the arrival latency's summary at the top
// (the stack benchmark's figures), "to_drives" the write latency's, the
// cycles the clock missed and command seq gaps.
nlohmann::json LatencyReport(const BridgeLoop& loop, std::int64_t deadline_misses);

}  // namespace edsp
