#include "edsp/kinematics/leg_effects.h"

#include <array>
#include <cmath>

namespace edsp::calibration {

namespace {

constexpr double kGravity = 9.80665;  // m/s² per g
constexpr double kDegreesPerRadian = 57.29577951308232;

struct Row {
  Effect effect;
  const char* name;
  int parameters;
  const char* title;
  double limit;        // ParameterLimit
  double prior_sigma;  // PriorSigma
};

// In the order of the enum (and of the diagnosis's design columns). Limits:
// docs/calibration.md; priors: far wider than any rig (docs/diagnosis.md).
constexpr std::array<Row, kEffectCount> kVocabulary = {{
    {Effect::kPassiveRotation, "passive_rotation", 2, "passive rotation (scale of the signed PR model)", 3.0, 10.0},
    {Effect::kLegOffset, "leg_offset", 6, "a constant length per leg", 10e-3, 5e-3},
    {Effect::kJointPosition, "joint_position", 36, "joint centres (base in B, platform in M)", 10e-3, 3e-4},
    {Effect::kLeadError, "lead_error", 6, "lead error (length per length of stroke)", 0.01, 1e-2},
    {Effect::kPeriodicLeadError, "periodic_lead_error", 12, "periodic lead error (once per screw turn)", 1e-3, 1e-3},
    {Effect::kBacklash, "backlash", 6, "play between the motor and the nut", 1e-3, 5e-3},
    // A limit of 0.1 s (s², s³): a 1.6 Hz position loop at most.
    {Effect::kServoLag, "servo_lag", 13, "the drives' following error", 0.1, 1.0},
    {Effect::kCompliance, "compliance", 9, "leg shortening under the moving mass' load", 0.01, 1e-2},
    {Effect::kThermalDrift, "thermal_drift", 4, "thermal drift (screw growth)", 0.1, 1e-3},
    // A gain of 1 is a point on a free mass; beyond 2 no structure carries A.
    {Effect::kStructuralResonance, "structural_resonance", 3,
     "a lightly damped mode of the structure carrying A, driven by its acceleration", 2.0, 1.0},
}};

constexpr bool InEnumOrder() {
  for (std::size_t k = 0; k < kVocabulary.size(); ++k) {
    if (static_cast<std::size_t>(kVocabulary[k].effect) != k) return false;
  }
  return true;
}
static_assert(InEnumOrder(), "kVocabulary must list the effects in the order of the enum");

using L = ParameterLayout;

// Every effect's θ, read in SI (the basis of leg_error_model.cpp) and in the
// units a rig team quotes. Typical sizes are those of a mid-size electric
// hexapod (docs/calibration.md): joint centres and leg zeros known to 0.1 mm,
// a lead to 100 ppm, a 40 Hz position loop, 20 N/µm legs under 800 kg, a
// screw warming 1 K per metre of travel and 2 K per quarter hour under power.
// clang-format off
constexpr ParameterGroup kParameterGroups[] = {
    // effect                     key                               layout               first stride offset typical  label                                                     unit                        unit_scale         decimals
    {Effect::kPassiveRotation,   "signed_pr_scale",                L::kScalar,          0,  0, 0.0, 0.1,     "PR the screws follow, × signed model",                  "×",                        1.0,               3},
    {Effect::kPassiveRotation,   "applied_compensation_scale",     L::kScalar,          1,  0, 1.0, 0.1,     "compensation the data's controller applied, × its mode", "×",                       1.0,               3},
    {Effect::kLegOffset,         "offset_m",                       L::kPerLeg,          0,  1, 0.0, 100e-6,  "offset",                                                "µm",                       1e6,               1},
    {Effect::kJointPosition,     "base_m",                         L::kPerLegXyz,       0,  3, 0.0, 100e-6,  "base",                                                  "µm",                       1e6,               1},
    {Effect::kJointPosition,     "platform_m",                     L::kPerLegXyz,       18, 3, 0.0, 100e-6,  "platform",                                              "µm",                       1e6,               1},
    {Effect::kLeadError,         "epsilon",                        L::kPerLeg,          0,  1, 0.0, 1e-4,    "lead error",                                            "ppm",                      1e6,               1},
    {Effect::kPeriodicLeadError, "amplitude_m",                    L::kPerLegAmplitude, 0,  2, 0.0, 10e-6,   "amplitude",                                             "µm",                       1e6,               1},
    {Effect::kPeriodicLeadError, "phase_rad",                      L::kPerLegPhase,     0,  2, 0.0, 10e-6,   "phase",                                                 "°",                        kDegreesPerRadian, 0},
    {Effect::kBacklash,          "backlash_m",                     L::kPerLeg,          0,  1, 0.0, 20e-6,   "play",                                                  "µm",                       1e6,               1},
    {Effect::kServoLag,          "lag_s",                          L::kPerLeg,          0,  1, 0.0, 4e-3,    "velocity lag",                                          "ms",                       1e3,               2},  // 1/(2π·40 Hz)
    {Effect::kServoLag,          "acceleration_lag_s2",            L::kPerLeg,          6,  1, 0.0, 1.6e-5,  "acceleration lag",                                      "ms²",                      1e6,               2},
    {Effect::kServoLag,          "jerk_lag_s3",                    L::kScalar,          12, 0, 0.0, 6e-8,    "jerk lag, all legs",                                    "ms³",                      1e9,               1},
    {Effect::kCompliance,        "mass_over_stiffness_s2",         L::kPerLeg,          0,  1, 0.0, 4e-5,    "per g of load",                                         "µm",                       1e6 * kGravity,    2},
    {Effect::kCompliance,        "moment_over_stiffness_s2_m",     L::kXyz,             6,  0, 0.0, 4e-6,    "c.o.m. moment term",                                    "µm·m per g",               1e6 * kGravity,    3},
    {Effect::kThermalDrift,      "growth_per_travel",              L::kScalar,          0,  0, 0.0, 7e-6,    "with recent travel",                                    "µm per m of travel",       1e6,               2},
    {Effect::kThermalDrift,      "growth_per_travel_stroke_per_m", L::kScalar,          1,  0, 0.0, 1.2e-5,  "with recent travel, per m of stroke",                   "µm per m of travel per m", 1e6,               2},
    {Effect::kThermalDrift,      "growth_powered_m_per_s",         L::kScalar,          2,  0, 0.0, 1.5e-8,  "with time under power",                                 "µm per hour",              3.6e9,             2},
    {Effect::kThermalDrift,      "growth_powered_stroke_per_s",    L::kScalar,          3,  0, 0.0, 2.5e-8,  "with time under power, per m of stroke",                "µm per hour per m",        3.6e9,             2},
    {Effect::kStructuralResonance, "gain",                         L::kXyz,             0,  0, 0.0, 0.2,     "modal gain (1: A on a free mass), along",              "×",                        1.0,               4},
};
// clang-format on

const Row& RowOf(Effect effect) { return kVocabulary[static_cast<std::size_t>(effect)]; }

bool IsPolar(const ParameterGroup& g) { return g.layout == L::kPerLegAmplitude || g.layout == L::kPerLegPhase; }

// Whether the group reads θ[k] (a polar pair reads its sine and its cosine).
bool Reads(const ParameterGroup& g, int k) {
  for (int v = 0; v < ValueCount(g); ++v) {
    const int at = ThetaIndex(g, v);
    if (k == at || (IsPolar(g) && k == at + 1)) return true;
  }
  return false;
}

}  // namespace

const std::vector<Effect>& AllEffects() {
  static const std::vector<Effect> all = [] {
    std::vector<Effect> v;
    for (const Row& r : kVocabulary) v.push_back(r.effect);
    return v;
  }();
  return all;
}

const char* EffectName(Effect effect) { return RowOf(effect).name; }

bool ParseEffect(const std::string& name, Effect* effect) {
  for (const Row& r : kVocabulary) {
    if (name == r.name) {
      *effect = r.effect;
      return true;
    }
  }
  return false;
}

int ParameterCount(Effect effect) { return RowOf(effect).parameters; }
const char* EffectTitle(Effect effect) { return RowOf(effect).title; }
double ParameterLimit(Effect effect) { return RowOf(effect).limit; }
double PriorSigma(Effect effect) { return RowOf(effect).prior_sigma; }

std::vector<ParameterGroup> ParameterGroups(Effect effect) {
  std::vector<ParameterGroup> groups;
  for (const ParameterGroup& g : kParameterGroups) {
    if (g.effect == effect) groups.push_back(g);
  }
  return groups;
}

bool IsPerLeg(const ParameterGroup& g) { return g.layout != L::kScalar && g.layout != L::kXyz; }
bool HasSigma(const ParameterGroup& g) { return !IsPolar(g); }
int ValuesPerLeg(const ParameterGroup& g) { return g.layout == L::kPerLegXyz ? 3 : 1; }

int ValueCount(const ParameterGroup& g) {
  if (g.layout == L::kScalar) return 1;
  if (g.layout == L::kXyz) return 3;
  return 6 * ValuesPerLeg(g);
}

int ThetaIndex(const ParameterGroup& g, int k) {
  switch (g.layout) {
    case L::kScalar: return g.first;
    case L::kXyz: return g.first + k;
    case L::kPerLegXyz: return g.first + g.stride * (k / 3) + k % 3;
    default: return g.first + g.stride * k;
  }
}

double GroupValue(const ParameterGroup& g, const double* theta, int k) {
  const int at = ThetaIndex(g, k);
  // A (sin, cos − 1) pair: the error is s·sin φ + c·(cos φ − 1) (leg_error_model.cpp).
  if (g.layout == L::kPerLegAmplitude) return std::hypot(theta[at], theta[at + 1]);
  if (g.layout == L::kPerLegPhase) return std::atan2(theta[at + 1], theta[at]);
  return g.offset + theta[at];
}

double TypicalParameterSize(Effect effect, int k) {
  for (const ParameterGroup& g : kParameterGroups) {
    if (g.effect == effect && Reads(g, k)) return g.typical_size;
  }
  return 0.0;
}

}  // namespace edsp::calibration
