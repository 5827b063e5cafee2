// edsp-actuator-bridge: EDSP_LEG_COMMAND → drive setpoints through a
// DriveBackend, encoders → EDSP_LEG_STATE, at 1 kHz. Holds the last valid
// position when commands go stale (50 ms) and reports it on EDSP_FAULT.
//   edsp-actuator-bridge [--backend virtual-rig|modbus-tcp] [--image-prefix edsp]
//                        [--config FILE] [--group FILE] [--session-id N]
//                        [--latency-report FILE] [--rejoin-speed-m-s V]
// A valid command goes to the drives the moment it arrives; the 1 kHz cycle
// checks staleness, re-writes the target and reads the encoders.
// --latency-report: on exit, JSON of setpoint → drive-setpoint latencies and
// cycles without a fresh command (the stack benchmark reads it).
#include <cstdio>
#include <fstream>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/actuator_bridge/modbus_tcp_backend.h"
#include "edsp/actuator_bridge/virtual_rig_backend.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/latency_recorder.h"
#include "edsp/node/node_options.h"
#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

#include <fmt/format.h>

namespace edsp {
namespace {

// --backend, or else the config's [drives] backend ("virtual": the rig's image).
std::unique_ptr<DriveBackend> MakeBackend(const std::string& name, const DrivesConfig& drives,
                                          const TransportConfig& transport, const std::string& image_prefix) {
  if (name == "virtual-rig") {
    return std::make_unique<VirtualRigBackend>(
        image_prefix.empty() ? transport.shm_prefix : image_prefix, transport.shm_permissions);
  }
  if (name == "modbus-tcp") return std::make_unique<ModbusTcpBackend>(drives);
  throw std::runtime_error("--backend " + name + ": known backends: virtual-rig, modbus-tcp");
}

void WriteLatencyReport(const std::string& path, const LatencyRecorder& latency,
                        std::int64_t deadline_misses, const ChannelCounters& in) {
  nlohmann::json report = ToJson(latency.Summarize());
  report["deadline_misses"] = deadline_misses;
  report["command_seq_gaps"] = in.seq_gaps + in.overruns;
  std::ofstream out(path);
  out << report.dump(2) << "\n";
  if (!out) std::fprintf(stderr, "edsp-actuator-bridge: cannot write %s\n", path.c_str());
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-actuator-bridge: leg commands → drives, encoders → leg states"};
  NodeOptions node;
  AddNodeOptions(&app, &node);
  std::string backend_name, image_prefix;
  int stale_ms = 50;
  app.add_option("--backend", backend_name, "drive backend: virtual-rig or modbus-tcp (default: [drives] backend)");
  app.add_option("--image-prefix", image_prefix, "process image segment prefix (default: shm_prefix)");
  app.add_option("--stale-ms", stale_ms, "hold when no valid command for this long")
      ->check(CLI::Range(1, 10000));
  double rejoin_speed_m_s = BridgeOptions{}.rejoin_speed_m_s;
  app.add_option("--rejoin-speed-m-s", rejoin_speed_m_s,
                 "after a re-arm, how fast the held legs go to the command stream")
      ->check(CLI::Range(1e-4, 0.5));
  std::string latency_report;
  app.add_option("--latency-report", latency_report, "write latency JSON here on exit");
  CLI11_PARSE(app, argc, argv);

  const PlatformConfig config = LoadConfigFile(node.config_path);
  const DrivesConfig drives = LoadDrivesConfig(node.config_path, config);
  if (backend_name.empty()) backend_name = drives.backend == "virtual" ? "virtual-rig" : drives.backend;
  const TransportConfig transport = TransportFor(node);
  InstallStopSignals();
  std::unique_ptr<DriveBackend> backend = MakeBackend(backend_name, drives, transport, image_prefix);
  std::string error;
  if (!backend->Configure(config, &error) || !backend->Activate(&error)) {
    throw std::runtime_error("drive backend " + backend_name + ": " + error);
  }
  BridgeOptions options;
  options.session_id = node.session_id;
  options.stale_us = std::int64_t{stale_ms} * 1000;
  options.rejoin_speed_m_s = rejoin_speed_m_s;
  ActuatorBridge bridge(PlatformModel(config), backend.get(), options);
  Bus bus(transport);
  auto states = bus.Advertise<leg_state_t>("EDSP_LEG_STATE");
  NodeReporting reporting(bus, "actuator_bridge");
  NodeStatus& status = reporting.status();
  LatencyRecorder latency;
  bus.Subscribe<leg_command_t>("EDSP_LEG_COMMAND", [&](const leg_command_t& command) {
    status.CountIn();
    fault_t fault;
    const bool was_rejoining = bridge.rejoining();
    if (!bridge.HandleCommand(command, UtimeNow(), &fault)) {
      status.CountRejected();
      reporting.Fault(fault);
      return;
    }
    if (was_rejoining && !bridge.rejoining()) {  // the hold is over
      reporting.Fault(MakeFault("actuator_bridge", "EDSP_LEG_COMMAND", FaultCode::kStale,
                                fault_t::SEVERITY_INFO,
                                fmt::format("rejoined the command stream at seq {}: following it again",
                                            command.seq),
                                UtimeNow()));
    }
    if (command.setpoint_utime > 0) latency.Record(UtimeNow() - command.setpoint_utime);
  });
  bus.Subscribe<arm_t>("EDSP_ARM", [&](const arm_t& arm) {
    const fault_t answer = bridge.HandleArm(arm, UtimeNow());
    if (answer.code == static_cast<std::int32_t>(FaultCode::kOperatorAction)) {
      std::fprintf(stderr, "edsp-actuator-bridge: re-armed by %s\n", arm.operator_name.c_str());
    }
    reporting.Fault(answer);
  });
  // Node-based map: the reference stays valid; no lookup in the 1 kHz loop.
  const ChannelCounters& in = bus.Counters("EDSP_LEG_COMMAND");
  RateClock clock(std::chrono::milliseconds(1));
  while (!StopRequested()) {
    for (auto left = clock.UntilNext(); left.count() > 0 && !StopRequested(); left = clock.UntilNext()) {
      bus.Handle(std::chrono::duration_cast<std::chrono::microseconds>(left));
    }
    clock.WaitNext();
    latency.EndCycle();
    const auto start = std::chrono::steady_clock::now();
    const std::int64_t now = UtimeNow();
    leg_state_t state;
    fault_t fault;
    if (bridge.Cycle(now, &state, &fault)) reporting.Fault(fault);
    if (states.Publish(state)) status.CountOut();
    status.SetState(bridge.holding() ? node_status_t::STATE_HOLDING : node_status_t::STATE_RUNNING);
    status.RecordLoop(std::chrono::steady_clock::now() - start);
    status.SetDrops(static_cast<std::int64_t>(in.seq_gaps + in.overruns));
    reporting.ReportUndecodable("EDSP_LEG_COMMAND", in, now);
    reporting.StatusTick(now, clock.missed());
  }
  backend->Deactivate();
  if (!latency_report.empty()) WriteLatencyReport(latency_report, latency, clock.missed(), in);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-actuator-bridge", edsp::Run, argc, argv); }
