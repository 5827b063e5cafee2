#include "edsp/kinematics/config.h"

#include <cmath>
#include <filesystem>
#include <initializer_list>

#include <fmt/format.h>

#include "edsp/kinematics/config_values.h"

namespace edsp {

namespace {

void ReadGeometry(const ConfigSection& s, const std::string& origin, PlatformConfig* config) {
  s.RejectUnknownKeys({"preset", "home_height_m", "base_joints_m", "platform_joints_m", "base_axes", "platform_axes"});
  config->preset = s.String("preset", "");
  if (!config->preset.empty() && config->preset != "huang2021") {
    throw ConfigError(
        fmt::format("{}: [geometry] preset = \"{}\" is unknown (known: huang2021)", origin, config->preset));
  }
  PlatformGeometry& g = config->geometry;
  Huang2021Dimensions dims;
  dims.home_height_m = s.Number("home_height_m", dims.home_height_m);
  if (!config->preset.empty()) g = Huang2021Geometry(dims);
  // Explicit arrays override the preset, one by one; without a preset all four
  // and the home height are required.
  const char* keys[] = {"base_joints_m", "platform_joints_m", "base_axes", "platform_axes"};
  Matrix36* targets[] = {&g.p_BoBi_B, &g.p_MoPi_M, &g.ja_B, &g.jd_M};
  for (int k = 0; k < 4; ++k) {
    if (!ReadLegRows(s, keys[k], targets[k]) && config->preset.empty()) {
      throw ConfigError(
          fmt::format("{}: missing key [geometry] {} (give it, or set preset = \"huang2021\")", origin, keys[k]));
    }
  }
  if (config->preset.empty() && !s.Has("home_height_m")) {
    throw ConfigError(fmt::format("{}: missing key [geometry] home_height_m", origin));
  }
  g.home_height_m = dims.home_height_m;
}

void ReadDrive(const ConfigSection& s, DriveParameters* drive) {
  s.RejectUnknownKeys({"lead_m", "pr_sign", "gear_ratio"});
  drive->lead_m = s.Number("lead_m", drive->lead_m);
  drive->pr_sign = static_cast<int>(s.Integer("pr_sign", drive->pr_sign));
  drive->gear_ratio = s.Number("gear_ratio", drive->gear_ratio);
}

void ReadLimits(const ConfigSection& s, WorkspaceLimits* limits) {
  s.RejectUnknownKeys({"leg_min_m", "leg_max_m", "joint_angle_max_rad", "jacobian_condition_max", "leg_speed_max_m_s"});
  limits->leg_speed_max_m_s = s.Number("leg_speed_max_m_s", limits->leg_speed_max_m_s);
  limits->leg_min_m = s.Number("leg_min_m", limits->leg_min_m);
  limits->leg_max_m = s.Number("leg_max_m", limits->leg_max_m);
  limits->joint_angle_max_rad = s.Number("joint_angle_max_rad", limits->joint_angle_max_rad);
  limits->jacobian_condition_max = s.Number("jacobian_condition_max", limits->jacobian_condition_max);
}

void ReadMotion(const ConfigSection& s, MotionLimits* m) {
  s.RejectUnknownKeys({"speed_max_m_s", "speed_max_rad_s", "accel_max_m_s2", "accel_max_rad_s2", "jerk_max_m_s3",
                       "jerk_max_rad_s3", "leg_accel_max_m_s2", "on_target_tolerance_m", "on_target_tolerance_rad",
                       "on_target_settle_s"});
  m->speed_max_m_s = s.Number("speed_max_m_s", m->speed_max_m_s);
  m->speed_max_rad_s = s.Number("speed_max_rad_s", m->speed_max_rad_s);
  m->accel_max_m_s2 = s.Number("accel_max_m_s2", m->accel_max_m_s2);
  m->accel_max_rad_s2 = s.Number("accel_max_rad_s2", m->accel_max_rad_s2);
  m->jerk_max_m_s3 = s.Number("jerk_max_m_s3", m->jerk_max_m_s3);
  m->jerk_max_rad_s3 = s.Number("jerk_max_rad_s3", m->jerk_max_rad_s3);
  m->leg_accel_max_m_s2 = s.Number("leg_accel_max_m_s2", m->leg_accel_max_m_s2);
  m->on_target_tolerance_m = s.Number("on_target_tolerance_m", m->on_target_tolerance_m);
  m->on_target_tolerance_rad = s.Number("on_target_tolerance_rad", m->on_target_tolerance_rad);
  m->on_target_settle_s = s.Number("on_target_settle_s", m->on_target_settle_s);
}

void Require(bool ok, const std::string& origin, const std::string& what) {
  if (!ok) throw ConfigError(fmt::format("{}: {}", origin, what));
}

// A motion limit must be a positive number no rig exceeds by orders of
// magnitude: above `most` it is a unit typo (mm for m), not a platform.
void RequireMotion(double value, double most, const char* key, const char* unit, const std::string& origin) {
  Require(std::isfinite(value) && value > 0.0 && value <= most, origin,
          fmt::format("[motion] {} = {} must be in (0, {}] {}", key, value, most, unit));
}

void ValidateMotion(const MotionLimits& m, const std::string& origin) {
  RequireMotion(m.speed_max_m_s, 10.0, "speed_max_m_s", "m/s", origin);
  RequireMotion(m.speed_max_rad_s, 10.0, "speed_max_rad_s", "rad/s", origin);
  RequireMotion(m.accel_max_m_s2, 100.0, "accel_max_m_s2", "m/s^2", origin);
  RequireMotion(m.accel_max_rad_s2, 100.0, "accel_max_rad_s2", "rad/s^2", origin);
  RequireMotion(m.jerk_max_m_s3, 10000.0, "jerk_max_m_s3", "m/s^3", origin);
  RequireMotion(m.jerk_max_rad_s3, 10000.0, "jerk_max_rad_s3", "rad/s^3", origin);
  RequireMotion(m.leg_accel_max_m_s2, 100.0, "leg_accel_max_m_s2", "m/s^2", origin);
  RequireMotion(m.on_target_tolerance_m, 0.01, "on_target_tolerance_m", "m", origin);
  RequireMotion(m.on_target_tolerance_rad, 0.01, "on_target_tolerance_rad", "rad", origin);
  Require(std::isfinite(m.on_target_settle_s) && m.on_target_settle_s >= 0.0 && m.on_target_settle_s <= 60.0, origin,
          fmt::format("[motion] on_target_settle_s = {} must be in [0, 60] s", m.on_target_settle_s));
}

}  // namespace

PlatformConfig Huang2021Config() {
  PlatformConfig config;
  config.preset = "huang2021";
  config.geometry = Huang2021Geometry();
  config.p_MoA_M = Vector3(Huang2021Dimensions{}.platform_radius_m, 0.0, 0.0);
  return config;
}

void ValidateConfig(const PlatformConfig& c, const std::string& origin) {
  ValidateGeometry(c.geometry, origin);
  const DriveParameters& d = c.drive;
  // A lead above 0.5 m per turn is no lead screw; a typo in units (mm for m).
  Require(d.lead_m > 0.0 && d.lead_m <= 0.5, origin,
          fmt::format("[drive] lead_m = {} must be in (0, 0.5] m per screw turn", d.lead_m));
  Require(d.pr_sign == 1 || d.pr_sign == -1, origin, fmt::format("[drive] pr_sign = {} must be 1 or -1", d.pr_sign));
  Require(d.gear_ratio > 0.0 && d.gear_ratio <= 1000.0, origin,
          fmt::format("[drive] gear_ratio = {} must be in (0, 1000] motor turns per screw turn", d.gear_ratio));
  Require(c.p_MoA_M.allFinite() && c.p_MoA_M.norm() <= 100.0, origin,
          "[observation] point_m must be finite and within 100 m of the platform centre");
  const WorkspaceLimits& l = c.limits;
  Require(l.leg_min_m > 0.0 && l.leg_min_m < l.leg_max_m, origin,
          fmt::format("[limits] leg_min_m = {} must be positive and below leg_max_m = {}", l.leg_min_m, l.leg_max_m));
  Require(l.joint_angle_max_rad > 0.0 && l.joint_angle_max_rad < kPi / 2, origin,
          fmt::format("[limits] joint_angle_max_rad = {} must be in (0, pi/2)", l.joint_angle_max_rad));
  // Above 10 m/s no lead-screw leg moves; a unit typo (mm/s for m/s).
  Require(l.leg_speed_max_m_s > 0.0 && l.leg_speed_max_m_s <= 10.0, origin,
          fmt::format("[limits] leg_speed_max_m_s = {} must be in (0, 10] m/s", l.leg_speed_max_m_s));
  Require(l.jacobian_condition_max >= 1.0, origin,
          fmt::format("[limits] jacobian_condition_max = {} must be at least 1", l.jacobian_condition_max));
  ValidateMotion(c.motion, origin);
}

PlatformConfig ParseConfig(const std::string& toml_text, const std::string& origin) {
  const ConfigFile file = ConfigFile::Parse(toml_text, origin);
  PlatformConfig config;
  const ConfigSection geometry = file.Section("geometry");
  Require(geometry.present(), origin, "missing section [geometry]");
  ReadGeometry(geometry, origin, &config);
  ReadDrive(file.Section("drive"), &config.drive);
  ReadLimits(file.Section("limits"), &config.limits);
  ReadMotion(file.Section("motion"), &config.motion);
  const ConfigSection observation = file.Section("observation");
  observation.RejectUnknownKeys({"point_m"});
  const bool preset_point = !config.preset.empty();
  Require(preset_point || observation.Has("point_m"), origin,
          "missing key [observation] point_m (no preset gives a default)");
  config.p_MoA_M = ReadVector3(observation, "point_m", Vector3(Huang2021Dimensions{}.platform_radius_m, 0.0, 0.0));
  const ConfigSection calibration = file.Section("calibration");
  calibration.RejectUnknownKeys({"model", "apply_ambiguous"});
  config.calibration_model = calibration.String("model", "");
  config.calibration_apply_ambiguous = calibration.Bool("apply_ambiguous", false);
  ValidateConfig(config, origin);
  return config;
}

std::string ReadConfigText(const std::string& path) { return ConfigFile::ReadText(path); }

PlatformConfig LoadConfigFile(const std::string& path) {
  PlatformConfig config = ParseConfig(ReadConfigText(path), path);
  const std::filesystem::path model(config.calibration_model);
  if (!config.calibration_model.empty() && model.is_relative()) {
    config.calibration_model = (std::filesystem::path(path).parent_path() / model).string();
  }
  return config;
}

}  // namespace edsp
