#include "edsp/rig/rig_effects.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "edsp/kinematics/leg_effects.h"
#include "edsp/kinematics/config_values.h"

namespace edsp {

namespace {

// Bounds that catch unit typos (mm for m, ppm for a fraction) on a platform
// of metres: an effect this large is a mistake, not a rig.
void RequireAll(const ConfigSection& s, const LegValues& v, const char* key, double lo, double hi, const char* what) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!(v[i] >= lo && v[i] <= hi)) {
      s.Fail(key, fmt::format("{} {} = {} (leg {}) must be in [{}, {}] {}", s.label(), key, v[i], i + 1, lo, hi, what));
    }
  }
}

// One value of a section in its range, or an error at its key's line.
void Require(const ConfigSection& s, bool ok, const char* key, double value, const char* range) {
  if (!ok) s.Fail(key, fmt::format("{} {} = {} must be {}", s.label(), key, value, range));
}

void ReadLegOffset(const ConfigSection& s, RigEffects::LegOffset* e) {
  s.RejectUnknownKeys({"enabled", "offset_m"});
  e->enabled = s.Bool("enabled", true);
  e->offset_m = ReadPerLeg(s, "offset_m", e->offset_m);
  RequireAll(s, e->offset_m, "offset_m", -0.01, 0.01, "m");
}

void ReadJointPosition(const ConfigSection& s, RigEffects::JointPosition* e) {
  s.RejectUnknownKeys({"enabled", "base_m", "platform_m"});
  e->enabled = s.Bool("enabled", true);
  ReadLegRows(s, "base_m", &e->base_m);
  ReadLegRows(s, "platform_m", &e->platform_m);
  if (e->base_m.cwiseAbs().maxCoeff() > 0.01 || e->platform_m.cwiseAbs().maxCoeff() > 0.01) {
    s.Fail("", fmt::format("{} joint offsets must be within ±0.01 m", s.label()));
  }
}

void ReadPassiveRotation(const ConfigSection& s, RigEffects::PassiveRotation* e) {
  s.RejectUnknownKeys({"enabled", "pr_sign", "pr_lead_m"});
  e->enabled = s.Bool("enabled", true);
  e->pr_sign = static_cast<int>(s.Integer("pr_sign", e->pr_sign));
  e->pr_lead_m = s.Number("pr_lead_m", e->pr_lead_m);
  if (e->pr_sign < -1 || e->pr_sign > 1) {
    s.Fail("pr_sign", fmt::format("{} pr_sign = {} must be 1, -1 or 0 (no PR)", s.label(), e->pr_sign));
  }
  if (e->pr_lead_m < 0.0 || e->pr_lead_m > 0.5) {
    s.Fail("pr_lead_m",
           fmt::format("{} pr_lead_m = {} must be in [0, 0.5] m (0: the nominal lead)", s.label(), e->pr_lead_m));
  }
}

void ReadLeadError(const ConfigSection& s, RigEffects::LeadError* e) {
  s.RejectUnknownKeys({"enabled", "epsilon"});
  e->enabled = s.Bool("enabled", true);
  e->epsilon = ReadPerLeg(s, "epsilon", e->epsilon);
  RequireAll(s, e->epsilon, "epsilon", -0.01, 0.01, "(a fraction: 100 ppm is 1e-4)");
}

void ReadPeriodicLeadError(const ConfigSection& s, RigEffects::PeriodicLeadError* e) {
  s.RejectUnknownKeys({"enabled", "amplitude_m", "phase_rad"});
  e->enabled = s.Bool("enabled", true);
  e->amplitude_m = ReadPerLeg(s, "amplitude_m", e->amplitude_m);
  e->phase_rad = ReadPerLeg(s, "phase_rad", e->phase_rad);
  RequireAll(s, e->amplitude_m, "amplitude_m", 0.0, 0.001, "m");
}

void ReadBacklash(const ConfigSection& s, RigEffects::Backlash* e) {
  s.RejectUnknownKeys({"enabled", "backlash_m"});
  e->enabled = s.Bool("enabled", true);
  e->backlash_m = ReadPerLeg(s, "backlash_m", e->backlash_m);
  RequireAll(s, e->backlash_m, "backlash_m", 0.0, 0.005, "m");
}

void ReadServoLag(const ConfigSection& s, RigEffects::ServoLag* e) {
  s.RejectUnknownKeys({"enabled", "inertia_kg_m2", "viscous_N_m_s", "torque_limit_N_m", "bandwidth_hz", "loop_rate_hz",
                       "coulomb_N_m", "integral_time_s", "screw_efficiency", "load_mass_kg",
                       "following_error_window_m"});
  e->coulomb_N_m = s.Number("coulomb_N_m", e->coulomb_N_m);
  e->integral_time_s = s.Number("integral_time_s", e->integral_time_s);
  e->screw_efficiency = s.Number("screw_efficiency", e->screw_efficiency);
  e->load_mass_kg = s.Number("load_mass_kg", e->load_mass_kg);
  e->following_error_window_m = s.Number("following_error_window_m", e->following_error_window_m);
  e->enabled = s.Bool("enabled", true);
  e->inertia_kg_m2 = s.Number("inertia_kg_m2", e->inertia_kg_m2);
  e->viscous_N_m_s = s.Number("viscous_N_m_s", e->viscous_N_m_s);
  e->torque_limit_N_m = s.Number("torque_limit_N_m", e->torque_limit_N_m);
  e->bandwidth_hz = s.Number("bandwidth_hz", e->bandwidth_hz);
  e->loop_rate_hz = s.Number("loop_rate_hz", e->loop_rate_hz);
  Require(s, e->inertia_kg_m2 > 0.0 && e->inertia_kg_m2 < 1.0, "inertia_kg_m2", e->inertia_kg_m2, "in (0, 1) kg m²");
  Require(s, e->viscous_N_m_s >= 0.0 && e->viscous_N_m_s < 10.0, "viscous_N_m_s", e->viscous_N_m_s, "in [0, 10) N m s");
  Require(s, e->torque_limit_N_m > 0.0 && e->torque_limit_N_m < 1000.0, "torque_limit_N_m", e->torque_limit_N_m,
          "in (0, 1000) N m");
  Require(s, e->bandwidth_hz > 0.0 && e->bandwidth_hz <= e->loop_rate_hz / 10.0, "bandwidth_hz", e->bandwidth_hz,
          "positive and at most a tenth of loop_rate_hz");
  Require(s, e->loop_rate_hz >= 1000.0 && e->loop_rate_hz <= 100000.0, "loop_rate_hz", e->loop_rate_hz,
          "in [1000, 100000] Hz");
  Require(s, e->coulomb_N_m >= 0.0 && e->coulomb_N_m < e->torque_limit_N_m, "coulomb_N_m", e->coulomb_N_m,
          "in [0, torque_limit_N_m) N m");
  Require(s,
          e->integral_time_s == 0.0 ||
              (e->integral_time_s >= 4.0 / (2.0 * 3.14159265358979 * e->bandwidth_hz) && e->integral_time_s <= 100.0),
          "integral_time_s", e->integral_time_s, "0 (none) or between 4/(2π·bandwidth_hz) and 100 s");
  Require(s, e->screw_efficiency > 0.1 && e->screw_efficiency <= 1.0, "screw_efficiency", e->screw_efficiency,
          "in (0.1, 1]");
  Require(s, e->load_mass_kg >= 0.0 && e->load_mass_kg <= 1e5, "load_mass_kg", e->load_mass_kg, "in [0, 1e5] kg");
  Require(s, e->following_error_window_m >= 0.0 && e->following_error_window_m <= 0.1, "following_error_window_m",
          e->following_error_window_m, "in [0, 0.1] m (0: none)");
}

void ReadCompliance(const ConfigSection& s, RigEffects::Compliance* e) {
  s.RejectUnknownKeys({"enabled", "stiffness_N_m", "mass_kg", "com_m", "payload_kg", "payload_com_m", "gravity_m_s2"});
  e->payload_kg = s.Number("payload_kg", e->payload_kg);
  e->payload_com_m = ReadVector3(s, "payload_com_m", e->payload_com_m);
  if (!(e->payload_kg >= 0.0 && e->payload_kg <= 1e5) || e->payload_com_m.norm() > 10.0) {
    s.Fail("", fmt::format("{} payload_kg = {} must be in [0, 1e5] kg, payload_com_m within 10 m", s.label(),
                           e->payload_kg));
  }
  e->enabled = s.Bool("enabled", true);
  e->stiffness_N_m = ReadPerLeg(s, "stiffness_N_m", e->stiffness_N_m);
  e->mass_kg = s.Number("mass_kg", e->mass_kg);
  e->com_m = ReadVector3(s, "com_m", e->com_m);
  e->gravity_m_s2 = ReadVector3(s, "gravity_m_s2", e->gravity_m_s2);
  RequireAll(s, e->stiffness_N_m, "stiffness_N_m", 1e5, 1e11, "N/m");
  if (!(e->mass_kg > 0.0 && e->mass_kg <= 1e5)) {
    s.Fail("mass_kg", fmt::format("{} mass_kg = {} must be in (0, 1e5] kg", s.label(), e->mass_kg));
  }
  if (e->com_m.norm() > 10.0 || e->gravity_m_s2.norm() > 100.0) {
    s.Fail("", fmt::format("{} com_m must be within 10 m of {{M}} and |gravity_m_s2| ≤ 100", s.label()));
  }
}

void ReadThermalDrift(const ConfigSection& s, RigEffects::ThermalDrift* e) {
  s.RejectUnknownKeys({"enabled", "alpha_per_K", "heating_K_per_m", "time_constant_s", "screw_length_m"});
  e->enabled = s.Bool("enabled", true);
  e->alpha_per_K = s.Number("alpha_per_K", e->alpha_per_K);
  e->heating_K_per_m = s.Number("heating_K_per_m", e->heating_K_per_m);
  e->time_constant_s = s.Number("time_constant_s", e->time_constant_s);
  e->screw_length_m = s.Number("screw_length_m", e->screw_length_m);
  Require(s, e->alpha_per_K >= 0.0 && e->alpha_per_K < 1e-3, "alpha_per_K", e->alpha_per_K, "in [0, 1e-3) per K");
  Require(s, e->heating_K_per_m >= 0.0 && e->heating_K_per_m < 100.0, "heating_K_per_m", e->heating_K_per_m,
          "in [0, 100) K/m");
  Require(s, e->time_constant_s > 0.0 && e->time_constant_s < 1e6, "time_constant_s", e->time_constant_s,
          "in (0, 1e6) s");
  Require(s, e->screw_length_m > 0.0 && e->screw_length_m < 10.0, "screw_length_m", e->screw_length_m, "in (0, 10) m");
}

void ReadStructuralResonance(const ConfigSection& s, RigEffects::StructuralResonance* e) {
  s.RejectUnknownKeys({"enabled", "frequency_hz", "damping", "gain"});
  e->enabled = s.Bool("enabled", true);
  e->frequency_hz = s.Number("frequency_hz", e->frequency_hz);
  e->damping = s.Number("damping", e->damping);
  e->gain = ReadVector3(s, "gain", e->gain);
  Require(s, e->frequency_hz >= 0.5 && e->frequency_hz <= 100.0, "frequency_hz", e->frequency_hz, "in [0.5, 100] Hz");
  Require(s, e->damping > 0.0 && e->damping < 1.0, "damping", e->damping, "in (0, 1)");
  Require(s, e->gain.cwiseAbs().maxCoeff() < 1.0, "gain", e->gain.cwiseAbs().maxCoeff(),
          "below 1 on every axis (1: A on a free mass)");
}

// The vocabulary, once: each effect of the kinematics' vocabulary
// (leg_effects.h) the rig simulates, its switch and its reader; its name,
// the [rig.effects.NAME] table, is the vocabulary's, so the rig and the
// diagnosis share one identity for it. Parsing, the enabled names, one
// effect alone and any() are driven from here: a new effect is one row and
// its Read function (and its physics).
struct EffectRow {
  calibration::Effect effect;
  bool& (*enabled)(RigEffects& e);
  bool (*is_enabled)(const RigEffects& e);
  void (*read)(const ConfigSection& s, RigEffects* e);
};

template <typename Physics, Physics RigEffects::*kMember, void (*kRead)(const ConfigSection&, Physics*)>
constexpr EffectRow Row(calibration::Effect effect) {
  return {effect, [](RigEffects& e) -> bool& { return (e.*kMember).enabled; },
          [](const RigEffects& e) { return (e.*kMember).enabled; },
          [](const ConfigSection& s, RigEffects* e) { kRead(s, &(e->*kMember)); }};
}

using E = RigEffects;
using V = calibration::Effect;
// In the order the rig lists them (EnabledEffects, the known names of an error).
constexpr EffectRow kEffects[] = {
    Row<E::LegOffset, &E::leg_offset, ReadLegOffset>(V::kLegOffset),
    Row<E::JointPosition, &E::joint_position, ReadJointPosition>(V::kJointPosition),
    Row<E::PassiveRotation, &E::passive_rotation, ReadPassiveRotation>(V::kPassiveRotation),
    Row<E::LeadError, &E::lead_error, ReadLeadError>(V::kLeadError),
    Row<E::PeriodicLeadError, &E::periodic_lead_error, ReadPeriodicLeadError>(V::kPeriodicLeadError),
    Row<E::Backlash, &E::backlash, ReadBacklash>(V::kBacklash),
    Row<E::ServoLag, &E::servo_lag, ReadServoLag>(V::kServoLag),
    Row<E::Compliance, &E::compliance, ReadCompliance>(V::kCompliance),
    Row<E::ThermalDrift, &E::thermal_drift, ReadThermalDrift>(V::kThermalDrift),
    Row<E::StructuralResonance, &E::structural_resonance, ReadStructuralResonance>(V::kStructuralResonance),
};

// One row per effect of the vocabulary and nothing else: the benchmark
// draws every effect the diagnosis can name on this rig, so none may lack a
// row, and two rows of one effect would give its table two readers.
// Effects outside the vocabulary, which the diagnosis must call `unknown`,
// are the blind rig's (blindrig/), not this one's: one added here would
// need a key other than calibration::Effect, and a place of its own in
// this check.
constexpr bool EachEffectOnce() {
  for (int e = 0; e < calibration::kEffectCount; ++e) {
    int rows = 0;
    for (const EffectRow& row : kEffects) rows += static_cast<int>(row.effect) == e;
    if (rows != 1) return false;
  }
  return std::size(kEffects) == static_cast<std::size_t>(calibration::kEffectCount);
}
static_assert(EachEffectOnce(), "kEffects must have one row per effect of the vocabulary (leg_effects.h)");

const char* NameOf(const EffectRow& row) { return calibration::EffectName(row.effect); }

const EffectRow* FindEffect(const std::string& name) {
  calibration::Effect effect;
  if (!calibration::ParseEffect(name, &effect)) return nullptr;
  for (const EffectRow& row : kEffects) {
    if (row.effect == effect) return &row;
  }
  return nullptr;
}

std::string KnownEffects() {
  std::string known;
  for (const EffectRow& row : kEffects) known += known.empty() ? NameOf(row) : fmt::format(", {}", NameOf(row));
  return known;
}

}  // namespace

bool RigEffects::any() const {
  return std::any_of(std::begin(kEffects), std::end(kEffects),
                     [this](const EffectRow& row) { return row.is_enabled(*this); });
}

RigEffects ParseRigEffects(const std::string& toml_text, const std::string& origin) {
  RigEffects effects;
  const ConfigSection rig = ConfigFile::Parse(toml_text, origin).Section("rig");
  rig.RejectUnknownKeys({"effects"});
  const ConfigSection all = rig.Table("effects");
  for (const std::string& name : all.Keys()) {
    const EffectRow* row = FindEffect(name);
    if (row == nullptr)
      all.Fail(name, fmt::format("unknown effect [rig.effects.{}] (known: {})", name, KnownEffects()));
    row->read(all.Table(name), &effects);
  }
  return effects;
}

RigEffects LoadRigEffects(const std::string& path) { return ParseRigEffects(ReadConfigText(path), path); }

std::vector<calibration::Effect> EnabledEffects(const RigEffects& e) {
  std::vector<calibration::Effect> enabled;
  for (const EffectRow& row : kEffects) {
    if (row.is_enabled(e)) enabled.push_back(row.effect);
  }
  return enabled;
}

RigEffects OnlyEffect(const RigEffects& e, calibration::Effect effect) {
  RigEffects only = e;
  for (const EffectRow& row : kEffects) row.enabled(only) = row.effect == effect && row.is_enabled(e);
  return only;
}

PlatformConfig TrueConfig(const PlatformConfig& nominal, const RigEffects& effects) {
  PlatformConfig truth = nominal;
  if (effects.joint_position.enabled) {
    truth.geometry.p_BoBi_B += effects.joint_position.base_m;
    truth.geometry.p_MoPi_M += effects.joint_position.platform_m;
  }
  return truth;
}

}  // namespace edsp
