#include "edsp/actuator_bridge/bridge_loop.h"
#include "edsp/channels.h"
#include "edsp/node/node_loop.h"

#include <cstdio>

#include <fmt/format.h>

namespace edsp {

BridgeLoop::BridgeLoop(Bus& bus, ActuatorBridge& bridge)
    : bus_(bus),
      bridge_(bridge),
      states_(bus.Advertise<leg_state_t>(channel::kLegState)),
      replies_(bus.Advertise<reply_t>(channel::kReply)),
      reporting_(bus, "actuator_bridge"),
      commands_in_(reporting_.WatchInput(bus, channel::kLegCommand, InputLosses::kCountedAsDrops)) {
  bus.Subscribe<leg_command_t>(channel::kLegCommand, [this](const leg_command_t& c) { OnCommand(c); });
  bus.Subscribe<arm_t>(channel::kArm, [this](const arm_t& arm) { OnArm(arm); });
}

void BridgeLoop::OnCommand(const leg_command_t& command) {
  reporting_.status().CountIn();
  fault_t fault;
  const bool was_rejoining = bridge_.rejoining();
  const std::int64_t now = UtimeNow();
  if (!bridge_.HandleCommand(command, now, &fault)) {
    reporting_.status().CountRejected();
    reporting_.Fault(fault);
    return;
  }
  if (was_rejoining && !bridge_.rejoining()) {  // the hold is over
    reporting_.Fault(MakeFault("actuator_bridge", channel::kLegCommand, FaultCode::kStale, fault_t::SEVERITY_INFO,
                               fmt::format("rejoined the command stream at seq {}: following it again", command.seq),
                               now));
  }
  if (command.setpoint_utime > 0) arrival_.Record(now - command.setpoint_utime);
}

void BridgeLoop::OnArm(const arm_t& arm) {
  const auto answer = bridge_.HandleArm(arm, UtimeNow());
  if (answer.acted) std::fprintf(stderr, "edsp-actuator-bridge: %s\n", answer.reply.reason.c_str());
  replies_.Publish(answer.reply);
}

void BridgeLoop::RunCycle(std::int64_t now_utime, std::int64_t deadline_misses) {
  const auto start = std::chrono::steady_clock::now();
  arrival_.EndCycle();
  written_.EndCycle();
  leg_state_t state;
  fault_t fault;
  if (bridge_.Cycle(now_utime, &state, &fault)) reporting_.Fault(fault);
  const std::int64_t written = bridge_.written_setpoint_utime();
  if (written != 0 && written != last_written_setpoint_utime_) written_.Record(now_utime - written);
  last_written_setpoint_utime_ = written;
  NodeStatus& status = reporting_.status();
  if (states_.Publish(state)) status.CountOut();
  status.SetState(bridge_.holding() ? node_status_t::STATE_HOLDING : node_status_t::STATE_RUNNING);
  reporting_.EndCycle(start, now_utime, deadline_misses);
}

void BridgeLoop::Run(CycleClock& clock, const std::function<bool()>& stop) {
  RunOnClock(bus_, clock, stop, [this](std::int64_t now, std::int64_t missed) {
    RunCycle(now, missed);
    return true;
  });
}

nlohmann::json LatencyReport(const BridgeLoop& loop, std::int64_t deadline_misses) {
  nlohmann::json report = ToJson(loop.arrival_latency().Summarize());
  report["to_drives"] = ToJson(loop.write_latency().Summarize());
  report["deadline_misses"] = deadline_misses;
  report["command_seq_gaps"] = loop.commands_in().seq_gaps + loop.commands_in().overruns;
  return report;
}

}  // namespace edsp
