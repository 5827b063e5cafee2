#include "edsp/cueing/cueing_config.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/config_file/config_file.h"

namespace edsp {
namespace {

Vector3 ReadVector(const ConfigSection& section, const char* key, const Vector3& fallback) {
  if (!section.Has(key)) return fallback;
  const std::vector<double> v = section.NumberOrNumbers(key, 3, 0.0);
  return Vector3(v[0], v[1], v[2]);
}

double Positive(const ConfigSection& section, const char* key, double fallback) {
  const double value = section.Number(key, fallback);
  if (!(value > 0.0)) section.Fail(key, fmt::format("{} {} = {} must be > 0", section.label(), key, value));
  return value;
}

Vector3 PositiveVector(const ConfigSection& section, const char* key, const Vector3& fallback) {
  const Vector3 value = ReadVector(section, key, fallback);
  if (!(value.array() > 0.0).all()) {
    section.Fail(key, fmt::format("{} {} = [{}, {}, {}]: every element must be > 0", section.label(), key, value.x(),
                                  value.y(), value.z()));
  }
  return value;
}

double Scale(const ConfigSection& section, const char* key, double fallback) {
  const double value = section.Number(key, fallback);
  if (!(value > 0.0 && value <= 1.0))
    section.Fail(key, fmt::format("{} {} = {} must be in (0, 1]", section.label(), key, value));
  return value;
}

void ReadCueing(const ConfigSection& s, CueingConfig& config) {
  s.RejectUnknownKeys({"rate_hz", "head_in_platform_m"});
  config.rate_hz = Positive(s, "rate_hz", config.rate_hz);
  if (config.rate_hz < 50.0 || config.rate_hz > 10000.0) {
    s.Fail("rate_hz", fmt::format("{} rate_hz = {} is outside 50..10000 Hz", s.label(), config.rate_hz));
  }
  config.head_in_platform_m = ReadVector(s, "head_in_platform_m", config.head_in_platform_m);
  if (config.head_in_platform_m.norm() > 5.0) {
    s.Fail("head_in_platform_m", fmt::format("{} head_in_platform_m is {} m from the platform's centre (at most 5 m)",
                                             s.label(), config.head_in_platform_m.norm()));
  }
}

void ReadInput(const ConfigSection& s, VehicleInputParameters& input) {
  s.RejectUnknownKeys({"timeout_s", "fade_s"});
  input.timeout_s = Positive(s, "timeout_s", input.timeout_s);
  input.fade_s = Positive(s, "fade_s", input.fade_s);
  if (input.timeout_s > 1.0) {
    s.Fail("timeout_s", fmt::format("{} timeout_s = {}: a rider would ride a second on a dead input (at most 1 s)",
                                    s.label(), input.timeout_s));
  }
}

void ReadWashout(const ConfigSection& s, ClassicalWashoutParameters& w) {
  s.RejectUnknownKeys({"specific_force_scale", "angular_velocity_scale", "translation_break_rad_s",
                       "translation_damping", "translation_washout_rad_s", "tilt_break_rad_s", "tilt_damping",
                       "tilt_rate_max_rad_s", "tilt_accel_max_rad_s2", "tilt_max_rad", "rotation_break_rad_s",
                       "rotation_damping"});
  w.specific_force_scale = Scale(s, "specific_force_scale", w.specific_force_scale);
  w.angular_velocity_scale = Scale(s, "angular_velocity_scale", w.angular_velocity_scale);
  w.translation_break_rad_s = PositiveVector(s, "translation_break_rad_s", w.translation_break_rad_s);
  w.translation_damping = Positive(s, "translation_damping", w.translation_damping);
  w.translation_washout_rad_s = PositiveVector(s, "translation_washout_rad_s", w.translation_washout_rad_s);
  w.tilt_break_rad_s = Positive(s, "tilt_break_rad_s", w.tilt_break_rad_s);
  w.tilt_damping = Positive(s, "tilt_damping", w.tilt_damping);
  w.tilt_rate_max_rad_s = Positive(s, "tilt_rate_max_rad_s", w.tilt_rate_max_rad_s);
  w.tilt_accel_max_rad_s2 = Positive(s, "tilt_accel_max_rad_s2", w.tilt_accel_max_rad_s2);
  w.tilt_max_rad = Positive(s, "tilt_max_rad", w.tilt_max_rad);
  if (w.tilt_max_rad >= 0.5 * kPi)
    s.Fail("tilt_max_rad", fmt::format("{} tilt_max_rad = {} must be under π/2", s.label(), w.tilt_max_rad));
  w.rotation_break_rad_s = PositiveVector(s, "rotation_break_rad_s", w.rotation_break_rad_s);
  w.rotation_damping = Positive(s, "rotation_damping", w.rotation_damping);
  try {
    ValidateWashout(w);
  } catch (const std::invalid_argument& e) {
    s.Fail("", fmt::format("{} {}", s.label(), e.what()));
  }
}

void ReadPerception(const ConfigSection& s, VestibularParameters& p) {
  s.RejectUnknownKeys({"otolith_tau_a_s", "otolith_tau_l_s", "otolith_tau_s_s", "otolith_threshold_m_s2",
                       "canal_tau_l_s", "canal_tau_s_s", "canal_tau_a_s", "canal_threshold_rad_s"});
  p.otolith.tau_a_s = Positive(s, "otolith_tau_a_s", p.otolith.tau_a_s);
  p.otolith.tau_l_s = Positive(s, "otolith_tau_l_s", p.otolith.tau_l_s);
  p.otolith.tau_s_s = Positive(s, "otolith_tau_s_s", p.otolith.tau_s_s);
  p.otolith.threshold_m_s2 = PositiveVector(s, "otolith_threshold_m_s2", p.otolith.threshold_m_s2);
  p.canal.tau_l_s = Positive(s, "canal_tau_l_s", p.canal.tau_l_s);
  p.canal.tau_s_s = Positive(s, "canal_tau_s_s", p.canal.tau_s_s);
  p.canal.tau_a_s = Positive(s, "canal_tau_a_s", p.canal.tau_a_s);
  p.canal.threshold_rad_s = PositiveVector(s, "canal_threshold_rad_s", p.canal.threshold_rad_s);
}

}  // namespace

CueingConfig ParseCueingConfig(const std::string& toml_text, const std::string& origin) {
  const ConfigFile file = ConfigFile::Parse(toml_text, origin);
  file.Root().RejectUnknownKeys({"cueing", "input", "washout", "perception"});
  CueingConfig config;
  ReadCueing(file.Section("cueing"), config);
  ReadInput(file.Section("input"), config.input);
  ReadWashout(file.Section("washout"), config.washout);
  ReadPerception(file.Section("perception"), config.perception);
  return config;
}

CueingConfig LoadCueingConfig(const std::string& path) { return ParseCueingConfig(ConfigFile::ReadText(path), path); }

}  // namespace edsp
