#pragma once
// One platform described by one TOML file (docs/config.md, interfaces.md §2).
// Loading validates everything; a bad file throws ConfigError whose message
// names the file, the [section] key and the value that is wrong.

#include <stdexcept>
#include <string>

#include "edsp/kinematics/geometry.h"

namespace edsp {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DriveParameters {
  double lead_m = 0.010;    // screw lead: travel per screw turn
  int pr_sign = 1;          // s in the PR model: thread hand and mounting, ±1
  double gear_ratio = 1.0;  // motor turns per screw turn
};

struct WorkspaceLimits {
  double leg_min_m = 1.40;
  double leg_max_m = 2.45;
  double joint_angle_max_rad = 75.0 * 3.14159265358979323846 / 180.0;  // leg axis vs platform normals
  double jacobian_condition_max = 50.0;  // of the length-normalised Jacobian, see workspace.h
  double leg_speed_max_m_s = 0.5;        // what the drives follow: the planner plans within
                                         // it, the bridge refuses faster steps as jumps
};

struct PlatformConfig {
  std::string preset;  // "huang2021" or empty
  PlatformGeometry geometry;
  DriveParameters drive;
  Vector3 p_MoA_M = Vector3::Zero();  // observation point A in {M}, m
  WorkspaceLimits limits;
  // [calibration]: an edsp-gap model the kinematics applies (calibration.h);
  // relative paths are taken from the config file's directory. Empty: none.
  std::string calibration_model;
  bool calibration_apply_ambiguous = false;
};

// The whole text of a config file. Throws ConfigError naming it if unreadable.
std::string ReadConfigText(const std::string& path);

// Reads and validates a config file. Throws ConfigError.
PlatformConfig LoadConfigFile(const std::string& path);

// Same, from TOML text; `origin` names the source in messages.
PlatformConfig ParseConfig(const std::string& toml_text, const std::string& origin);

// The built-in huang2021 config with every default (what an empty
// `[geometry] preset = "huang2021"` file yields).
PlatformConfig Huang2021Config();

// Checks drive, limits and observation values. Throws ConfigError.
void ValidateConfig(const PlatformConfig& config, const std::string& origin);

}  // namespace edsp
