#pragma once
// The effect vocabulary of interfaces.md §4 (kinematics/leg_effects.h: a
// parameterised leg-length error Δl(θ), linear in θ) and what the diagnosis
// adds to it: which effects nest, their parameters named with units, and
// the measurements that tell them apart.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "edsp/kinematics/leg_effects.h"
#include "edsp/kinematics/verdict.h"

namespace edsp::gap {

using calibration::AllEffects;
using calibration::Effect;
using calibration::EffectName;
using calibration::EffectTitle;
using calibration::kEffectCount;
using calibration::ParameterCount;
using calibration::ParameterGroup;
using calibration::ParameterGroups;
using calibration::ParseEffect;
using calibration::PriorSigma;
using calibration::Verdict;
using calibration::VerdictFromName;
using calibration::VerdictName;

// Whether `simple` is (nearly) a special case of `rich`, so that `rich` can
// always do what `simple` does with more parameters: leg offsets are joint
// centres moved along the legs at home. Such a pair is never ambiguous: the
// simpler is chosen unless the richer is clearly better held out.
bool IsNestedIn(Effect simple, Effect rich);

// Its parameters as JSON, named with units (e.g. {"backlash_m": [...]}),
// read from θ by the vocabulary's parameter groups (leg_effects.h).
nlohmann::json ParametersJson(Effect effect, const double* theta);
// The 1-σ of the same values, under the same keys; a value read from two θ
// (a periodic error's amplitude and phase) has none and is left out, so the
// object is empty for an effect whose every value is such.
nlohmann::json SigmaJson(Effect effect, const double* sigma);

// The measurement that would tell `a` from `b` apart when the data cannot.
std::string SeparatingMeasurement(Effect a, Effect b);

}  // namespace edsp::gap
