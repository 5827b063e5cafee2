#pragma once
// Six simulated CiA 402 drives serving the shared-memory CSP image
// (csp_shm_image.h) on their own clock: each cycle they take the master's
// newest RxPDOs, step, and latch their TxPDOs. What edsp-drive-sim --serve
// shm runs, and what a test drives directly; an EtherCAT master process
// would stand here for real drives. Their axes are the simulator's own or
// another's physics (csp_axes.h).

#include <functional>
#include <memory>
#include <string>

#include "edsp/drives/served_cabinet.h"
#include "edsp/transport/shm_channel.h"

namespace edsp::cia402 {

struct ShmDriveServerOptions {
  std::string prefix = "edsp";  // the segments' prefix (csp_shm_image.h)
  mode_t permissions = 0600;
  double cycle_s = 0.001;  // the drives' own cycle
  SimulatedDriveOptions drive;
};

class CspShmServer {
 public:
  // Claims the TxPDO ring; throws std::runtime_error naming it and why
  // (another live server holds it). Null `axes`: six bounded-speed axes.
  explicit CspShmServer(const ShmDriveServerOptions& options, std::unique_ptr<CspAxes> axes = nullptr);

  // Serves until `stop()` says so.
  void Run(const std::function<bool()>& stop);
  void InjectFault(int index, std::uint16_t error_code) { cabinet_.InjectFault(index, error_code); }
  // The drives stop cycling (true): nothing new is latched, as a gateway
  // whose drives' clock stopped; false lets them cycle again.
  void StopDrivesClock(bool stopped) { cabinet_.StopDrivesClock(stopped); }
  std::string endpoint() const { return "cia402-shm " + options_.prefix; }

 private:
  // The master's newest RxPDOs into the cabinet (the ring looked for again
  // when its writer, a restarted bridge, is new).
  void TakeCommands();
  void Latch();

  ShmDriveServerOptions options_;
  ServedCabinet cabinet_;
  std::unique_ptr<ShmWriter> feedback_;
  std::unique_ptr<ShmReader> commands_;
  std::int64_t next_look_utime_ = 0;
};

}  // namespace edsp::cia402
