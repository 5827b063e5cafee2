// edsp-drive-sim: six simulated CiA 402 drives (cyclic synchronous
// position) behind a Modbus TCP server at edsp's register map
// (docs/drives.md), for the bridge's Modbus backend and its tests.
#include <cstdio>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "edsp/drives/modbus_drive_server.h"
#include "edsp/node/runtime.h"

namespace {

int Run(int argc, char** argv) {
  edsp::cia402::DriveServerOptions options;
  double cycle_ms = 1.0, fieldbus_timeout_ms = 20.0;
  CLI::App app{"Six simulated CiA 402 drives (CSP) behind a Modbus TCP server"};
  app.add_option("--host", options.host, "address to listen on")->capture_default_str();
  app.add_option("--port", options.port, "TCP port (0: any free one, printed)")->capture_default_str()
      ->check(CLI::Range(0, 65535));
  app.add_option("--cycle-ms", cycle_ms, "the drives' own cycle")->capture_default_str()->check(CLI::Range(0.05, 100.0));
  app.add_option("--following-window-counts", options.drive.following_error_window,
                 "6065h: following error beyond this faults the drive (8611h)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-speed-counts-s", options.drive.max_speed_counts_s, "the axes' speed limit")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--fieldbus-timeout-ms", fieldbus_timeout_ms,
                 "no command for this long while enabled faults the drive (8130h)")
      ->capture_default_str()->check(CLI::Range(1.0, 10000.0));
  CLI11_PARSE(app, argc, argv);
  options.cycle_s = cycle_ms * 1e-3;
  options.drive.fieldbus_timeout_s = fieldbus_timeout_ms * 1e-3;
  edsp::InstallStopSignals();
  edsp::cia402::ModbusDriveServer server(options);
  std::printf("edsp-drive-sim: 6 drives on modbus-tcp %s:%d\n", options.host.c_str(), server.port());
  std::fflush(stdout);
  server.Run([] { return edsp::StopRequested(); });
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return edsp::RunMain("edsp-drive-sim", Run, argc, argv); }
