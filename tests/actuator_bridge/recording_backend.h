#pragma once
// A fake drive backend for the bridge's unit tests: perfect drives that
// follow what they were told, or stopped elsewhere, or silent.
#include <array>
#include <optional>
#include <string>

#include "edsp/drive_io/drive_backend.h"

namespace edsp {

class RecordingBackend final : public DriveBackend {
 public:
  bool Configure(const PlatformConfig&, std::string*) override { return true; }
  bool Activate(std::string*) override { return true; }
  void Deactivate() override {}
  bool Read(std::int64_t, DriveFeedback* feedback) override {
    exchanges += 'R';
    if (!answering) return false;  // drives silent (a frozen rig, a lost fieldbus)
    feedback->motor_angle_rad = stopped_at ? *stopped_at : written.motor_angle_rad;  // a perfect drive
    feedback->status = status;
    feedback->utime = latched_utime;
    return true;
  }
  bool Write(std::int64_t, const DriveSetpoint& setpoint) override {
    exchanges += 'W';
    written = setpoint;
    ++writes;
    return true;
  }
  bool Reset(std::string* error) override {
    exchanges += 'X';
    if (!resettable) *error = "drive 3: fault 7500h (communication) persists";
    return resettable;
  }
  BackendState state() const override { return BackendState::kActive; }
  std::string Detail() const override { return detail; }
  std::string detail;  // why it fails, as a backend would say
  DriveSetpoint written;
  bool resettable = true;
  int writes = 0;
  std::string exchanges;  // 'R' per Read, 'W' per Write, 'X' per Reset, in order
  bool answering = true;
  std::int64_t latched_utime = 0;                   // the instant the drives say their reading describes (0: none)
  std::optional<std::array<double, 6>> stopped_at;  // drives that stopped elsewhere
  std::array<DriveStatus, 6> status{DriveStatus::kEnabled, DriveStatus::kEnabled, DriveStatus::kEnabled,
                                    DriveStatus::kEnabled, DriveStatus::kEnabled, DriveStatus::kEnabled};
};

}  // namespace edsp
