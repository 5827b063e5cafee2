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

}  // namespace edsp::calibration
