#pragma once
// The effect vocabulary of interfaces.md §4 as the diagnosis models it: each
// effect is a parameterised leg-length error Δl(θ) added to the nominal
// model, linear in its parameters θ (see docs/diagnosis.md for each basis).

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace edsp::gap {

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

// Whether `simple` is (nearly) a special case of `rich`, so that `rich` can
// always do what `simple` does with more parameters: leg offsets are joint
// centres moved along the legs at home. Such a pair is never ambiguous: the
// simpler is chosen unless the richer is clearly better held out.
bool IsNestedIn(Effect simple, Effect rich);

// Number of parameters θ of the effect's leg-space basis.
int ParameterCount(Effect effect);

// Its parameters as JSON, named with units (e.g. {"backlash_m": [...]}).
nlohmann::json ParametersJson(Effect effect, const double* theta);

// The measurement that would tell `a` from `b` apart when the data cannot.
std::string SeparatingMeasurement(Effect a, Effect b);
// The same against the tracker frame (a nuisance the diagnosis estimates).
std::string SeparatingMeasurementFromFrame(Effect a);

}  // namespace edsp::gap
