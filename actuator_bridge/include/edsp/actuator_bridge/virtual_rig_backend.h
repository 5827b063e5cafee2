#pragma once
// DriveBackend for drives behind the shared-memory process image (the
// edsp-rig process today; the same image could front a fieldbus master).
// Read() reports failure when the bridge has watched the drives stay silent
// for `timeout_us` (its own pauses not counted: transport/watched_silence.h),
// or when one reports a fault (it braked: the rig's following-error window).
// Its drives reset their faults when disabled, so it is never in fault
// itself: their silence or a drive's fault is the bridge's to latch.

#include <memory>
#include <string>

#include "edsp/drive_io/backend_lifecycle.h"
#include "edsp/drive_io/drive_process_image.h"
#include "edsp/transport/shm_channel.h"
#include "edsp/transport/watched_silence.h"

namespace edsp {

class VirtualRigBackend final : public DriveBackend {
 public:
  VirtualRigBackend(std::string segment_prefix, mode_t permissions = 0600, std::int64_t timeout_us = 50000);
  bool Configure(const PlatformConfig& config, std::string* error) override;
  // Waits up to 5 s for the drives' feedback channel to appear.
  bool Activate(std::string* error) override;
  void Deactivate() override;
  void Cleanup() override;
  bool Read(std::int64_t now_utime, DriveFeedback* feedback) override;
  bool Write(std::int64_t now_utime, const DriveSetpoint& setpoint) override;
  BackendState state() const override { return lifecycle_.state(); }
  std::string Detail() const override;

 private:
  bool Publish(std::int64_t now_utime, const DriveSetpoint& setpoint, bool enable);

  std::string prefix_;
  mode_t permissions_;
  std::int64_t timeout_us_;
  BackendLifecycle lifecycle_;
  std::unique_ptr<ShmWriter> commands_;
  std::unique_ptr<ShmReader> feedback_;
  DriveFeedback last_;
  bool heard_ = false;
  WatchedSilence silence_;
  std::int64_t cycle_ = 0;
};

}  // namespace edsp
