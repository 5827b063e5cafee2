#pragma once
// The process image the actuator bridge and the drives exchange every cycle,
// as a fieldbus master exposes it: one command record out, one feedback
// record in, each on its own shared-memory channel (edsp's seqlock ring), so
// the rig process can stand where the drives will.

#include <cstdint>
#include <string>

#include "edsp/drive_io/drive_backend.h"

namespace edsp {

struct DriveImageCommand {
  std::int64_t utime;
  std::int64_t cycle;
  std::uint8_t enable;
  double motor_angle_rad[6];
  double motor_velocity_rad_s[6];
};

struct DriveImageFeedback {
  std::int64_t utime;
  std::int64_t cycle;
  double motor_angle_rad[6];
  double motor_velocity_rad_s[6];
  std::int8_t status[6];
};

// Layout fingerprints checked by the segments (bump on any change).
inline constexpr std::int64_t kDriveImageCommandFingerprint = 0x4544535044494331;   // "EDSPDIC1"
inline constexpr std::int64_t kDriveImageFeedbackFingerprint = 0x4544535044494631;  // "EDSPDIF1"

inline std::string DriveCommandSegment(const std::string& prefix) { return prefix + ".drive.command"; }
inline std::string DriveFeedbackSegment(const std::string& prefix) { return prefix + ".drive.feedback"; }

}  // namespace edsp
