#pragma once
// One platform described by one TOML file (docs/config.md, interfaces.md §2).
// Loading validates everything; a bad file throws ConfigError whose message
// names the file, the [section] key and the value that is wrong.

#include <string>

#include "edsp/config_file/config_error.h"
#include "edsp/kinematics/geometry.h"

namespace edsp {

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

// [motion]: what the planner's motion service plans moves within (the
// pivot's speed, acceleration and jerk, the rotation's, the legs'
// acceleration) and when it calls a move on target. A move may ask for
// less, never for more.
struct MotionLimits {
  double speed_max_m_s = 0.1;
  double speed_max_rad_s = 0.2;
  double accel_max_m_s2 = 0.5;
  double accel_max_rad_s2 = 1.0;
  double jerk_max_m_s3 = 5.0;
  double jerk_max_rad_s3 = 10.0;
  double leg_accel_max_m_s2 = 5.0;       // the drives' acceleration: checked along every path, sets stop's deceleration
  double on_target_tolerance_m = 10e-6;  // measured pivot position within this of the target
  double on_target_tolerance_rad = 50e-6;  // and its rotation within this
  double on_target_settle_s = 0.1;         // for this long
};

struct PlatformConfig {
  std::string preset;  // "huang2021" or empty
  PlatformGeometry geometry;
  DriveParameters drive;
  Vector3 p_MoA_M = Vector3::Zero();  // observation point A in {M}, m
  WorkspaceLimits limits;
  MotionLimits motion;
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

// Checks drive, limits, motion and observation values. Throws ConfigError.
void ValidateConfig(const PlatformConfig& config, const std::string& origin);

}  // namespace edsp
