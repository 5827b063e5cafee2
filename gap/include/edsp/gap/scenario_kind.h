#pragma once
// What a benchmark scenario holds, which decides how it is scored: nothing,
// one effect, two, an effect outside the diagnosis's vocabulary, or a whole
// rig of every class at once. The names are the benchmark JSON's `kind`
// (and the blind rig's draws).

#include <cstddef>
#include <optional>
#include <string>

namespace edsp::gap {

enum class ScenarioKind { kNone, kSingle, kPair, kOutOfVocabulary, kWholeRig };

const char* ScenarioKindName(ScenarioKind kind);
std::optional<ScenarioKind> ParseScenarioKind(const std::string& name);
// The kind of a scenario of `effects` effects of the vocabulary (0, 1, 2+).
ScenarioKind KindOfEffects(std::size_t effects);

}  // namespace edsp::gap
