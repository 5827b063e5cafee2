#pragma once
// What edsp-gap says of an effect of the vocabulary (leg_effects.h): found
// for sure, tied with another explanation, or not there. It lives in the
// kinematics because a calibration decides from it what it applies
// (calibration.h's AppliesEntry). Its names are the report's and the model
// file's `verdict` (interfaces.md §4), which users' scripts read.

#include <optional>
#include <string_view>

namespace edsp::calibration {

enum class Verdict { kIdentified, kAmbiguous, kRejected };

const char* VerdictName(Verdict verdict);  // "identified", "ambiguous", "rejected"
// The verdict a name stands for; none when it names no verdict.
std::optional<Verdict> VerdictFromName(std::string_view name);

}  // namespace edsp::calibration
