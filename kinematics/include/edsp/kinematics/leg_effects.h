#pragma once
// The vocabulary of leg-length effects (docs/diagnosis.md, interfaces.md §4):
// what edsp-gap identifies and what a calibration compensates. Each effect
// is a parameterised leg-length error Δl = B(state)·θ, linear in θ
// (leg_error_model.h). One table (leg_effects.cpp) holds each effect's name,
// parameter count, limits and prior, and how its parameters read: adding an
// effect adds its row and parameter groups there, and its basis.

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
  kStructuralResonance,
};

inline constexpr int kEffectCount = 10;

const std::vector<Effect>& AllEffects();
const char* EffectName(Effect effect);
bool ParseEffect(const std::string& name, Effect* effect);

// Number of parameters θ of the effect's leg-space basis.
int ParameterCount(Effect effect);

// What the effect is, in a few words for report.md's headings.
const char* EffectTitle(Effect effect);

// The largest |θ| a real platform of any size has: beyond it a model file is
// not a calibration of a platform but a fit gone wrong (calibration.h).
double ParameterLimit(Effect effect);

// edsp-gap's prior 1-σ of each θ: far wider than any real rig's value; it
// only pins directions the data cannot see (ridge regression).
double PriorSigma(Effect effect);

// How a group of θ is laid out: per leg (θ[first + stride·leg]), a point per
// leg (θ[first + 3·leg + axis]), the amplitude or phase of a per-leg
// (sin, cos − 1) pair at θ[first + stride·leg], one value, or one xyz vector.
enum class ParameterLayout { kPerLeg, kPerLegXyz, kPerLegAmplitude, kPerLegPhase, kScalar, kXyz };

// A named group of an effect's parameters: its JSON key in SI (edsp-gap's
// report and model, interfaces.md §4) and how report.md shows it.
struct ParameterGroup {
  Effect effect;
  const char* key;  // e.g. "offset_m"
  ParameterLayout layout;
  int first;            // θ index of leg 1's value (or of the value)
  int stride;           // per-leg layouts: from one leg's θ to the next's
  double offset;        // the value read is offset + θ (a scale read as 1 + θ)
  double typical_size;  // TypicalParameterSize of its θ
  const char* label;    // report.md: the value's name,
  const char* unit;     //   its unit,
  double unit_scale;    //   SI → that unit,
  int decimals;         //   and the digits shown
};

// The effect's groups, in reading order; together they read every θ.
std::vector<ParameterGroup> ParameterGroups(Effect effect);

bool IsPerLeg(const ParameterGroup& group);     // a value (or point) per leg
bool HasSigma(const ParameterGroup& group);     // reads one θ per value (not a polar pair)
int ValuesPerLeg(const ParameterGroup& group);  // per-leg: 1 or 3 (xyz)
int ValueCount(const ParameterGroup& group);    // scalar 1, xyz 3, per leg 6 × ValuesPerLeg

// The θ index of value `k` of the group (per leg: k = leg·ValuesPerLeg + axis;
// for a polar pair its sine's index).
int ThetaIndex(const ParameterGroup& group, int k);
// Value `k` of the group read from θ, in SI.
double GroupValue(const ParameterGroup& group, const double* theta, int k);

// What parameter k of the effect amounts to on a real rig (in its own unit:
// m, s, s², per metre of travel, ...): the scale at which a motion set's
// identifiability is judged (planner/identifiability.h), so that columns of
// metres, seconds and ratios meet on equal terms. 0 for a k the effect does
// not have.
double TypicalParameterSize(Effect effect, int k);

}  // namespace edsp::calibration
