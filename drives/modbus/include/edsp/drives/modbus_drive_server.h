#pragma once
// Six simulated CiA 402 drives behind a Modbus TCP server (libmodbus), at
// the register map of modbus_register_map.h: what edsp-drive-sim serves,
// and what a test talks to over loopback. The drives run on their own
// clock; requests are answered as they come, one client at a time (a new
// connection replaces the old one, as a restarted master's does). Their
// axes are the simulator's own or another's physics (csp_axes.h).

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "edsp/drives/csp_axes.h"
#include "edsp/drives/served_cabinet.h"
#include "edsp/drives/modbus_register_map.h"

typedef struct _modbus modbus_t;
typedef struct _modbus_mapping_t modbus_mapping_t;

namespace edsp::cia402 {

struct DriveServerOptions {
  std::string host = "127.0.0.1";
  int port = 1502;         // 0: any free port (see port())
  double cycle_s = 0.001;  // the drives' own cycle
  SimulatedDriveOptions drive;
};

class ModbusDriveServer {
 public:
  // Binds and listens; throws std::runtime_error naming host:port and why.
  // Null `axes`: six bounded-speed axes at count 0 (options.drive's speed).
  explicit ModbusDriveServer(const DriveServerOptions& options, std::unique_ptr<CspAxes> axes = nullptr);
  ~ModbusDriveServer();
  ModbusDriveServer(const ModbusDriveServer&) = delete;
  ModbusDriveServer& operator=(const ModbusDriveServer&) = delete;

  int port() const { return port_; }
  // Serves until `stop()` says so.
  void Run(const std::function<bool()>& stop);
  // From any thread: drive `index` (0-5) raises `error_code` at its next cycle.
  void InjectFault(int index, std::uint16_t error_code) { cabinet_.InjectFault(index, error_code); }
  // From any thread: the drives stop cycling (true) while the server goes
  // on answering with what they last latched, as a gateway whose drives'
  // clock stopped; false lets them cycle again.
  void StopDrivesClock(bool stopped) { cabinet_.StopDrivesClock(stopped); }
  std::int64_t requests() const { return requests_.load(); }

 private:
  void Latch();  // the cabinet's latched feedbacks into the feedback block
  void Serve(int client);
  void CloseClient();

  DriveServerOptions options_;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* mapping_ = nullptr;
  int listener_ = -1;
  int client_ = -1;
  int port_ = 0;
  ServedCabinet cabinet_;
  std::atomic<std::int64_t> requests_{0};
};

}  // namespace edsp::cia402
