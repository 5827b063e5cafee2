#include "edsp/kinematics/leg_effects.h"

#include <array>

namespace edsp::calibration {

namespace {

struct Row {
  Effect effect;
  const char* name;
  int parameters;
};

// In the order of the enum (and of the diagnosis's design columns).
constexpr std::array<Row, kEffectCount> kVocabulary = {{
    {Effect::kPassiveRotation, "passive_rotation", 2},        // signed-PR scale, applied-compensation scale − 1
    {Effect::kLegOffset, "leg_offset", 6},
    {Effect::kJointPosition, "joint_position", 36},           // 6 base + 6 platform joint centres, xyz
    {Effect::kLeadError, "lead_error", 6},
    {Effect::kPeriodicLeadError, "periodic_lead_error", 12},  // sin and (cos − 1) per leg
    {Effect::kBacklash, "backlash", 6},
    {Effect::kServoLag, "servo_lag", 13},                     // velocity and acceleration lag per leg, one jerk lag
    {Effect::kCompliance, "compliance", 9},                   // m/k per leg, m·c/k̄ (xyz) shared
    {Effect::kThermalDrift, "thermal_drift", 4},              // travel and time drivers, on a fixed length and the stroke
}};

constexpr bool InEnumOrder() {
  for (std::size_t k = 0; k < kVocabulary.size(); ++k) {
    if (static_cast<std::size_t>(kVocabulary[k].effect) != k) return false;
  }
  return true;
}
static_assert(InEnumOrder(), "kVocabulary must list the effects in the order of the enum");

const Row& RowOf(Effect effect) { return kVocabulary[static_cast<std::size_t>(effect)]; }

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

namespace {

// Parameters [first, next row's first) of an effect share one size.
struct TypicalSize {
  Effect effect;
  int first;
  double size;
};

// Orders of magnitude of a mid-size electric hexapod (docs/calibration.md):
// joint centres and leg zeros known to 0.1 mm, a lead to 100 ppm, a 40 Hz
// position loop, 20 N/µm legs under 800 kg, a screw warming 1 K per metre of
// travel and 2 K per quarter hour under power.
constexpr std::array<TypicalSize, 15> kTypicalSizes = {{
    {Effect::kPassiveRotation, 0, 0.1},
    {Effect::kLegOffset, 0, 100e-6},
    {Effect::kJointPosition, 0, 100e-6},
    {Effect::kLeadError, 0, 1e-4},
    {Effect::kPeriodicLeadError, 0, 10e-6},
    {Effect::kBacklash, 0, 20e-6},
    {Effect::kServoLag, 0, 4e-3},     // s: 1/(2π·40 Hz)
    {Effect::kServoLag, 6, 1.6e-5},   // s²
    {Effect::kServoLag, 12, 6e-8},    // s³
    {Effect::kCompliance, 0, 4e-5},   // m/k per leg, s²
    {Effect::kCompliance, 6, 4e-6},   // m·c/k̄, s²·m
    {Effect::kThermalDrift, 0, 7e-6},  // per metre of travel heat
    {Effect::kThermalDrift, 1, 1.2e-5},
    {Effect::kThermalDrift, 2, 1.5e-8},  // per second under power
    {Effect::kThermalDrift, 3, 2.5e-8},
}};

}  // namespace

double TypicalParameterSize(Effect effect, int k) {
  double size = 0.0;
  for (const TypicalSize& t : kTypicalSizes) {
    if (t.effect == effect && t.first <= k) size = t.size;
  }
  return size;
}

}  // namespace edsp::calibration
