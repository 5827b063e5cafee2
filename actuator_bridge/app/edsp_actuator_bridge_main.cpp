// edsp-actuator-bridge: EDSP_LEG_COMMAND → drive setpoints through a
// DriveBackend, encoders → EDSP_LEG_STATE, at 1 kHz. Holds the last valid
// position when commands go stale (50 ms) and reports it on EDSP_FAULT.
//   edsp-actuator-bridge [--backend virtual-rig|modbus-tcp|cia402-shm] [--image-prefix edsp]
//                        [--config FILE] [--group FILE] [--session-id N]
//                        [--latency-report FILE] [--rejoin-speed-m-s V] [--cycle-phase-us P]
// Each 1 kHz cycle reads the drives once, checks staleness and writes the
// latest valid command once (bridge_loop.h); it ticks P µs after the host's
// millisecond grid, where the planner ticks, unless the backend owns the clock.
// --latency-report: on exit, JSON of setpoint → bridge and setpoint → drive
// write latencies and cycles without a fresh command (the stack benchmark reads it).
#include <cstdio>
#include <fstream>
#include <optional>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/actuator_bridge/bridge_loop.h"
#include "edsp/actuator_bridge/backend_registry.h"
#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

#include <fmt/format.h>

namespace edsp {
namespace {

void WriteLatencyReport(const std::string& path, const nlohmann::json& report) {
  std::ofstream out(path);
  out << report.dump(2) << "\n";
  if (!out) std::fprintf(stderr, "edsp-actuator-bridge: cannot write %s\n", path.c_str());
}

int Run(int argc, char** argv) {
  NodeApp app{"edsp-actuator-bridge: leg commands → drives, encoders → leg states"};
  std::string backend_name, image_prefix;
  int stale_ms = 50;
  app.add_option("--backend", backend_name, "drive backend: " + KnownBackends() + " (default: [drives] backend)");
  app.add_option("--image-prefix", image_prefix, "process image segment prefix (default: shm_prefix)");
  app.add_option("--stale-ms", stale_ms, "hold when no valid command for this long")->check(CLI::Range(1, 10000));
  double rejoin_speed_m_s = BridgeOptions{}.rejoin_speed_m_s;
  app.add_option("--rejoin-speed-m-s", rejoin_speed_m_s,
                 "after a re-arm, how fast the held legs go to the command stream")
      ->check(CLI::Range(1e-4, 0.5));
  std::string latency_report;
  app.add_option("--latency-report", latency_report, "write latency JSON here on exit");
  int cycle_phase_us = static_cast<int>(kBridgePhase.count());
  app.add_option("--cycle-phase-us", cycle_phase_us,
                 "the cycle's tick after the host's millisecond grid (the planner's tick)")
      ->check(CLI::Range(0, 999));
  CLI11_PARSE(app, argc, argv);

  const PlatformConfig config = LoadConfigFile(app.node.config_path);
  const DrivesConfig drives = LoadDrivesConfig(app.node.config_path, config);
  if (!drives.backend_note.empty())
    std::fprintf(stderr, "edsp-actuator-bridge: [drives] %s\n", drives.backend_note.c_str());
  if (backend_name.empty()) backend_name = drives.backend;
  const TransportConfig transport = TransportFor(app.node);
  InstallStopSignals();
  std::string note;
  std::optional<ActiveBackend> backend;
  backend.emplace(backend_name, BackendContext{drives, transport, image_prefix}, config, &note);
  if (!note.empty()) std::fprintf(stderr, "edsp-actuator-bridge: --backend: %s\n", note.c_str());
  BridgeOptions options;
  options.session_id = app.node.session_id;
  options.stale_us = std::int64_t{stale_ms} * 1000;
  options.rejoin_speed_m_s = rejoin_speed_m_s;
  ActuatorBridge bridge(PlatformModel(config), backend->get(), options);
  Bus bus(transport);
  BridgeLoop loop(bus, bridge);
  RateClock own_clock(kBridgePeriod, std::chrono::microseconds(cycle_phase_us));
  CycleClock* clock = backend->get()->Clock() != nullptr ? backend->get()->Clock() : &own_clock;
  loop.Run(*clock, [] { return StopRequested(); });
  const nlohmann::json report = LatencyReport(loop, clock->missed());
  backend.reset();  // the drives deactivated before anything else is done
  if (!latency_report.empty()) WriteLatencyReport(latency_report, report);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-actuator-bridge", edsp::Run, argc, argv); }
