#include "edsp/cueing/cueing_config.h"

#include <cmath>
#include <optional>
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
  s.RejectUnknownKeys({"rate_hz", "head_in_platform_m", "algorithm"});
  const std::string algorithm = s.String("algorithm", CueingAlgorithmName(config.algorithm));
  const std::optional<CueingAlgorithm> named = CueingAlgorithmFromName(algorithm);
  if (!named) {
    s.Fail("algorithm", fmt::format("{} algorithm = \"{}\": not one of classical_washout, mpc", s.label(), algorithm));
  }
  config.algorithm = *named;
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

Vector6 PositiveAxes(const ConfigSection& section, const char* key, const Vector6& fallback) {
  if (!section.Has(key)) return fallback;
  const std::vector<double> v = section.Numbers(key, 6);
  Vector6 value;
  for (int j = 0; j < 6; ++j) {
    if (!(v[static_cast<std::size_t>(j)] > 0.0)) {
      section.FailAtElement(key, static_cast<std::size_t>(j),
                            fmt::format("{} {}[{}] = {}: every axis's limit must be > 0 (x y z roll pitch yaw)",
                                        section.label(), key, j, v[static_cast<std::size_t>(j)]));
    }
    value(j) = v[static_cast<std::size_t>(j)];
  }
  return value;
}

double NonNegative(const ConfigSection& section, const char* key, double fallback) {
  const double value = section.Number(key, fallback);
  if (!(value >= 0.0)) section.Fail(key, fmt::format("{} {} = {} must be ≥ 0", section.label(), key, value));
  return value;
}

void ReadMpc(const ConfigSection& s, MpcCueingParameters& m) {
  s.RejectUnknownKeys({"position_max", "velocity_max", "acceleration_max", "jerk_max", "leg_margin", "demand_fade_s",
                       "perceived_force_weight", "perceived_rate_weight", "position_penalty", "velocity_penalty",
                       "acceleration_penalty", "jerk_penalty", "terminal_penalty", "horizon_discount_s",
                       "solve_period_s", "fine_intervals", "coarse_interval_s", "coarse_intervals"});
  m.wanted.position = PositiveAxes(s, "position_max", m.wanted.position);
  m.wanted.velocity = PositiveAxes(s, "velocity_max", m.wanted.velocity);
  m.wanted.acceleration = PositiveAxes(s, "acceleration_max", m.wanted.acceleration);
  m.jerk_max = PositiveAxes(s, "jerk_max", m.jerk_max);
  m.leg_margin = NonNegative(s, "leg_margin", m.leg_margin);
  if (m.leg_margin > 0.5)
    s.Fail("leg_margin", fmt::format("{} leg_margin = {} must be at most 0.5", s.label(), m.leg_margin));
  m.demand_fade_s = Positive(s, "demand_fade_s", m.demand_fade_s);
  MpcPenalties& w = m.penalties;
  w.perceived_force = NonNegative(s, "perceived_force_weight", w.perceived_force);
  w.perceived_rate = NonNegative(s, "perceived_rate_weight", w.perceived_rate);
  w.position = NonNegative(s, "position_penalty", w.position);
  w.velocity = NonNegative(s, "velocity_penalty", w.velocity);
  w.acceleration = NonNegative(s, "acceleration_penalty", w.acceleration);
  w.jerk = NonNegative(s, "jerk_penalty", w.jerk);
  w.terminal = NonNegative(s, "terminal_penalty", w.terminal);
  w.horizon_discount_s = NonNegative(s, "horizon_discount_s", w.horizon_discount_s);
  MpcHorizon& h = m.horizon;
  h.solve_period_s = Positive(s, "solve_period_s", h.solve_period_s);
  h.fine_intervals = static_cast<int>(s.Integer("fine_intervals", h.fine_intervals, 1, 100));
  h.coarse_interval_s = Positive(s, "coarse_interval_s", h.coarse_interval_s);
  h.coarse_intervals = static_cast<int>(s.Integer("coarse_intervals", h.coarse_intervals, 0, 100));
  try {
    ValidateMpc(m);
  } catch (const std::invalid_argument& e) {
    s.Fail("", e.what());
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
  file.Root().RejectUnknownKeys({"cueing", "input", "washout", "mpc", "perception"});
  CueingConfig config;
  ReadCueing(file.Section("cueing"), config);
  ReadInput(file.Section("input"), config.input);
  ReadWashout(file.Section("washout"), config.washout);
  ReadMpc(file.Section("mpc"), config.mpc);
  ReadPerception(file.Section("perception"), config.perception);
  return config;
}

CueingConfig LoadCueingConfig(const std::string& path) { return ParseCueingConfig(ConfigFile::ReadText(path), path); }

}  // namespace edsp
