#pragma once
// DriveBackend for six CiA 402 drives (CSP), whatever carries their process
// image (CspLink): a Modbus TCP server at edsp's register map (modbus-tcp:
// `edsp-drive-sim`, or a gateway in front of real drives), or the
// shared-memory image on this host (cia402-shm: `edsp-drive-sim --serve
// shm`, or an EtherCAT master process; docs/drives.md). One exchange per
// cycle, in Write: the cycle's setpoint out and the six feedbacks in, which
// the next cycle's Read returns, as a fieldbus master's inputs are one
// exchange old. Activate enables the drives through
// the state machine without moving them. A failed exchange or a drive that
// leaves operation (a fault, a quick stop) puts the backend in fault
// (backend_lifecycle.h): it reports why, keeps cycling with the last
// targets it took, leaves the drives out of operation without power, and
// resets or re-enables none on its own: only Reset (the operator's re-arm)
// does that and recovers. A lost connection is retried every 100 ms.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "edsp/drive_io/backend_lifecycle.h"
#include "edsp/drive_io/drive_backend.h"
#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/drives/csp_link.h"

namespace edsp {

class Cia402Backend final : public DriveBackend {
 public:
  Cia402Backend(const DrivesConfig& config, std::unique_ptr<cia402::CspLink> link);
  bool Configure(const PlatformConfig& config, std::string* error) override;
  // Connects (5 s at most) and enables every drive not in fault where it
  // stands; a faulted one stays so until Reset (the operator's re-arm).
  bool Activate(std::string* error) override;
  void Deactivate() override;
  void Cleanup() override;
  // False also when a drive has left operation (the bridge then holds and
  // latches, as for silent drives).
  bool Read(std::int64_t now_utime, DriveFeedback* feedback) override;
  bool Write(std::int64_t now_utime, const DriveSetpoint& setpoint) override;
  BackendState state() const override { return lifecycle_.state(); }
  // The operator's re-arm: fault reset and enable of the drives out of
  // operation, where they stand; the others keep power and their targets.
  // In fault, recovers once every drive is in operation again.
  bool Reset(std::string* error) override;
  // Why the last cycle failed, or which drive is out of operation and why.
  std::string Detail() const override { return detail_; }

 private:
  // Which drives out of operation an exchange may bring back.
  enum class Enabling { kNone, kNotFaulted, kResetFaults };
  // One exchange: each drive's next command carrying its held target.
  bool Exchange(Enabling enabling, std::string* error);
  using CycleCounts = std::array<std::uint16_t, 6>;
  // How long enabling may take: at start-up, and in a re-arm (between two
  // of the bridge's cycles, which it holds up meanwhile).
  static constexpr std::chrono::milliseconds kActivateBudget{5000};
  static constexpr std::chrono::milliseconds kReArmBudget{250};
  // Exchanges until every drive the call may enable is in operation, or
  // `budget` has passed.
  bool EnableDrives(Enabling enabling, std::chrono::milliseconds budget, std::string* error);
  // Every drive in operation, but those `enabling` leaves in fault.
  bool Enabled(Enabling enabling) const;
  // Every drive's feedback was latched after the exchange that read `before`.
  bool LatchedSince(const CycleCounts& before) const;
  bool ConnectAndRead(std::string* error);
  void Describe(DriveFeedback* feedback);
  // Shutdown (6040h) to every drive: ready to switch on, no power.
  void PowerDown();
  // An active backend's cycle failed: in fault, remembering why.
  void Fail(const std::string& why);

  DrivesConfig config_;
  std::unique_ptr<cia402::CspLink> link_;
  BackendLifecycle lifecycle_;
  std::string fault_cause_;  // what put it in fault
  cia402::CspCommands commands_{};
  cia402::CspFeedbacks feedback_{};
  std::array<std::optional<std::int32_t>, 6> target_counts_{};
  std::array<std::int32_t, 6> velocity_counts_{};
  std::int64_t last_connect_utime_ = -1;
  std::string detail_;
};

}  // namespace edsp
