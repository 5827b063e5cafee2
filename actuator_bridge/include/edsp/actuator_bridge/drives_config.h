#pragma once
// [drives] of the platform config: which DriveBackend the bridge uses and,
// for real drives, where they are and how their counts map to the legs.
//
//   [drives]
//   backend = "modbus-tcp"         # or "cia402-shm" (the CSP image in shared memory on this
//                                  # host), or "virtual-rig" (the rig's process image; the
//                                  # default; "virtual" is its old spelling): backend_registry.h
//   host = "127.0.0.1"             # the Modbus TCP server of the six drives
//   port = 1502
//   response_timeout_ms = 5        # an exchange's answer (cia402-shm: a newly latched image)
//   counts_per_m = 104857600       # encoder counts per metre of leg travel: a number or 6
//   offset_counts = 0              # each drive's count at the leg's home: a number or 6
//   direction = 1                  # +1 or -1 (a motor mounted the other way): a number or 6

#include <array>
#include <optional>
#include <string>

#include "edsp/drives/csp_image.h"
#include "edsp/kinematics/config.h"

namespace edsp {

struct DrivesConfig {
  std::string backend = "virtual-rig";  // a BackendKinds() name
  std::string backend_note;             // the config gave an old spelling: this says the new one
  std::string host = "127.0.0.1";
  int port = 1502;
  double response_timeout_s = 0.005;
  // Motor angle ↔ counts per drive (from counts_per_m, the lead and the gear).
  std::array<cia402::DriveScaling, 6> scaling{};
};

// Nothing when every drive's scaling is usable, else which leg and why, naming
// the [drives] keys it comes from (a backend given counts by --backend
// while the config's [drives] declares none has a scaling of 0).
std::optional<std::string> ScalingProblem(const std::array<cia402::DriveScaling, 6>& scaling);

// Throws ConfigError naming the file, line and key.
DrivesConfig ParseDrivesConfig(const std::string& toml_text, const std::string& origin, const DriveParameters& drive);
DrivesConfig LoadDrivesConfig(const std::string& path, const PlatformConfig& platform);

}  // namespace edsp
