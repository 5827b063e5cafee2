#pragma once
// Six simulated CiA 402 drives behind edsp's Modbus TCP server on a free
// loopback port, served on a thread for as long as the object lives (a
// test's drive cabinet; destroying it is the simulator going away).

#include <atomic>
#include <memory>
#include <thread>

#include "edsp/drives/modbus_drive_server.h"

namespace edsp::test_support {

class ServedDrives {
 public:
  // `cycle_s`: the drives' own clock (a slow one makes every TxPDO the
  // master reads many of its requests old).
  explicit ServedDrives(int port = 0, double cycle_s = 0.001) {
    cia402::DriveServerOptions options;
    options.port = port;
    options.cycle_s = cycle_s;
    options.drive.fieldbus_timeout_s = 2.0;  // the tests' cycles are paced by a busy machine, not 1 ms
    server_ = std::make_unique<cia402::ModbusDriveServer>(options);
    thread_ = std::thread([this] { server_->Run([this] { return stop_.load(); }); });
  }
  ~ServedDrives() {
    stop_ = true;
    thread_.join();
  }
  ServedDrives(const ServedDrives&) = delete;
  ServedDrives& operator=(const ServedDrives&) = delete;

  cia402::ModbusDriveServer& server() { return *server_; }
  int port() const { return server_->port(); }

 private:
  std::unique_ptr<cia402::ModbusDriveServer> server_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace edsp::test_support
