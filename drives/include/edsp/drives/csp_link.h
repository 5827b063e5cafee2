#pragma once
// What carries six drives' CSP process images between a master and the
// drives, one exchange per cycle: Modbus TCP (modbus_drive_master.h), or a
// shared-memory image that a drive simulator or an EtherCAT master process
// serves on the same host (csp_shm_master.h). The CiA 402 master logic
// above it (the bridge's Cia402Backend) is the same whatever carries it.

#include <array>
#include <string>

#include "edsp/drives/csp_axes.h"
#include "edsp/drives/csp_image.h"

namespace edsp::cia402 {

using CspCommands = std::array<CspCommand, kCabinetDrives>;
using CspFeedbacks = std::array<CspFeedback, kCabinetDrives>;

class CspLink {
 public:
  virtual ~CspLink() = default;
  // Reaches the drives; false with *error naming the endpoint and why.
  virtual bool Connect(std::string* error) = 0;
  virtual bool connected() const = 0;
  // One cycle: `commands` out, the drives' latest latched feedback in.
  // False with *error (and disconnected) when the exchange failed.
  virtual bool Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error) = 0;
  // The feedback alone, writing nothing (what the drives are after a
  // reconnect, before any command is built on it).
  virtual bool ReadFeedback(CspFeedbacks* feedback, std::string* error) = 0;
  virtual void Disconnect() = 0;
  // What a report names: "modbus-tcp host:port", "cia402-shm <prefix>".
  virtual std::string endpoint() const = 0;
};

}  // namespace edsp::cia402
