// edsp-drive-sim: six simulated CiA 402 drives (cyclic synchronous
// position) behind a Modbus TCP server at edsp's register map, or serving
// the CSP image in shared memory (--serve shm, docs/drives.md), for the
// bridge's CiA 402 backends and their tests.
//   edsp-drive-sim [--serve modbus|shm] [--host 127.0.0.1] [--port 1502] [--cycle-ms 1]
//                  [--following-window-counts N] [--fieldbus-timeout-ms 20]
//                  [--axes own|rig] [--image-prefix P] [--fault-drive N] [--fault-code HEX]
//                  [--config FILE] [--group FILE]
// --axes own: each drive moves its own axis at a bounded speed.
// --axes rig: the drives move the virtual rig's legs through its process
// image (edsp-rig computes the physics and the tracker), counts scaled by
// the config's [drives] section: the sim-modbus group.
// --serve shm: the image's segments are <shm_prefix>.cia402.rxpdo/.txpdo
// (the group's transport, or --csp-prefix), as an EtherCAT master process
// would serve them for real drives.
// SIGUSR1 faults one drive (--fault-drive, error code --fault-code) as a
// real drive's own fault would: a drill of the master's fault handling.
#include <csignal>
#include <cstdio>

#include <atomic>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/actuator_bridge/virtual_rig_backend.h"
#include "edsp/drive_sim/backend_axes.h"
#include "edsp/drives/csp_shm_server.h"
#include "edsp/drives/modbus_drive_server.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"

namespace edsp {
namespace {

std::atomic<bool> g_fault_requested{false};
void OnFaultSignal(int) { g_fault_requested.store(true); }

void InstallFaultSignal() {
  struct sigaction action {};
  action.sa_handler = OnFaultSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGUSR1, &action, nullptr);
}

// The rig's legs behind the drives, through the image the bridge's
// virtual backend would otherwise write.
std::unique_ptr<cia402::CspAxes> RigAxes(const NodeOptions& node, const std::string& image_prefix,
                                         double fieldbus_timeout_s) {
  const PlatformConfig config = LoadConfigFile(node.config_path);
  const DrivesConfig drives = LoadDrivesConfig(node.config_path, config);
  const TransportConfig transport = TransportFor(node);
  auto image = std::make_unique<VirtualRigBackend>(image_prefix.empty() ? transport.shm_prefix : image_prefix,
                                                   transport.shm_permissions);
  return std::make_unique<cia402::BackendAxes>(std::move(image), config, drives.scaling,
                                               static_cast<std::int64_t>(fieldbus_timeout_s * 1e6));
}

// Serves until stopped, SIGUSR1 faulting `fault_drive` (1-6) with `fault_code`.
template <typename Server>
void Serve(Server& server, int fault_drive, std::uint16_t fault_code) {
  server.Run([&] {
    if (g_fault_requested.exchange(false)) {
      server.InjectFault(fault_drive - 1, fault_code);
      std::fprintf(stderr, "edsp-drive-sim: drive %d faulted (error code %04Xh) on SIGUSR1\n", fault_drive, fault_code);
    }
    return StopRequested();
  });
}

int Run(int argc, char** argv) {
  cia402::DriveServerOptions options;
  double cycle_ms = 1.0, fieldbus_timeout_ms = 20.0;
  std::string axes = "own", image_prefix, serve = "modbus", csp_prefix;
  int fault_drive = 1;
  std::uint16_t fault_code = 0xFF01;
  NodeApp app{"Six simulated CiA 402 drives (CSP) behind a Modbus TCP server or a shared-memory image"};
  app.add_option("--serve", serve, "modbus: a Modbus TCP server; shm: the CSP image in shared memory")
      ->capture_default_str()
      ->check(CLI::IsMember({"modbus", "shm"}));
  app.add_option("--csp-prefix", csp_prefix, "--serve shm: the image's segment prefix (default: shm_prefix)");
  app.add_option("--host", options.host, "address to listen on")->capture_default_str();
  app.add_option("--port", options.port, "TCP port (0: any free one, printed)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  app.add_option("--cycle-ms", cycle_ms, "the drives' own cycle")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 100.0));
  app.add_option("--following-window-counts", options.drive.following_error_window,
                 "6065h: following error beyond this faults the drive (8611h)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-speed-counts-s", options.drive.max_speed_counts_s, "the own axes' speed limit")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--fieldbus-timeout-ms", fieldbus_timeout_ms,
                 "no command for this long while enabled faults the drive (8130h)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 10000.0));
  app.add_option("--axes", axes, "own: each drive's own axis; rig: the virtual rig's legs (its process image)")
      ->capture_default_str()
      ->check(CLI::IsMember({"own", "rig"}));
  app.add_option("--image-prefix", image_prefix, "the rig's process image prefix (default: shm_prefix)");
  app.add_option("--fault-drive", fault_drive, "the drive SIGUSR1 faults")
      ->capture_default_str()
      ->check(CLI::Range(1, 6));
  app.add_option("--fault-code", fault_code,
                 "its error code (603Fh), e.g. 0x2310; default FF01h (manufacturer-specific)")
      ->check(CLI::Range(1, 0xFFFF));
  CLI11_PARSE(app, argc, argv);
  options.cycle_s = cycle_ms * 1e-3;
  options.drive.fieldbus_timeout_s = fieldbus_timeout_ms * 1e-3;
  InstallStopSignals();
  InstallFaultSignal();
  auto axes_of = [&] {
    return axes == "rig" ? RigAxes(app.node, image_prefix, options.drive.fieldbus_timeout_s) : nullptr;
  };
  if (serve == "shm") {
    cia402::ShmDriveServerOptions shm;
    shm.prefix = csp_prefix.empty() ? TransportFor(app.node).shm_prefix : csp_prefix;
    shm.permissions = TransportFor(app.node).shm_permissions;
    shm.cycle_s = options.cycle_s;
    shm.drive = options.drive;
    cia402::CspShmServer server(shm, axes_of());
    std::printf("edsp-drive-sim: 6 drives (%s axes) on %s\n", axes.c_str(), server.endpoint().c_str());
    std::fflush(stdout);
    Serve(server, fault_drive, fault_code);
    return 0;
  }
  cia402::ModbusDriveServer server(options, axes_of());
  std::printf("edsp-drive-sim: 6 drives (%s axes) on modbus-tcp %s:%d\n", axes.c_str(), options.host.c_str(),
              server.port());
  std::fflush(stdout);
  Serve(server, fault_drive, fault_code);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-drive-sim", edsp::Run, argc, argv); }
