#pragma once
// The vocabulary of leg-length effects (docs/diagnosis.md, interfaces.md §4):
// what edsp-gap identifies and what a calibration compensates. Each effect
// is a parameterised leg-length error Δl = B(state)·θ, linear in θ
// (leg_error_model.h). One table holds each effect's name and parameter
// count; adding an effect adds a row there and its basis.

#include <string>
#include <vector>

namespace edsp::calibration {

enum class Effect {
  kPassiveRotation,
  kLegOffset,
  kJointPosition,
  kLeadError,
  kPeriodicLeadError,
  kBacklash,
  kServoLag,
  kCompliance,
  kThermalDrift,
};

inline constexpr int kEffectCount = 9;

const std::vector<Effect>& AllEffects();
const char* EffectName(Effect effect);
bool ParseEffect(const std::string& name, Effect* effect);

// Number of parameters θ of the effect's leg-space basis.
int ParameterCount(Effect effect);

// What parameter k of the effect amounts to on a real rig (in its own unit:
// m, s, s², per metre of travel, ...): the scale at which a motion set's
// identifiability is judged (planner/identifiability.h), so that columns of
// metres, seconds and ratios meet on equal terms.
double TypicalParameterSize(Effect effect, int k);

}  // namespace edsp::calibration
