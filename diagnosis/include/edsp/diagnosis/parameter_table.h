#pragma once
// The found effects' parameters as a person reads them in report.md: one
// Markdown table per effect, per leg where the effect is per leg, in the
// units a rig team quotes (µm, ppm, ms, µm per g, µm per metre of travel),
// each value with its 1-σ from the fit. The JSON keeps SI (interfaces.md §4).

#include <string>

#include "edsp/diagnosis/diagnose.h"

namespace edsp::gap {

// "12.3 ± 0.4" (σ omitted when not finite or not fitted). `decimals` digits.
std::string ValueWithSigma(double value, double sigma, int decimals);

// The Markdown table of one effect's parameters (θ and σ in SI, as fitted),
// headed by the effect's name and its units; empty if it has no parameters.
std::string ParameterTableMarkdown(const EffectResult& effect);

}  // namespace edsp::gap
