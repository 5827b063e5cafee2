#include "edsp/gap/scenario_kind.h"

#include <iterator>

namespace edsp::gap {

namespace {

constexpr const char* kScenarioKindNames[] = {"none", "single", "pair", "out_of_vocabulary", "whole_rig"};

}  // namespace

const char* ScenarioKindName(ScenarioKind kind) { return kScenarioKindNames[static_cast<int>(kind)]; }

std::optional<ScenarioKind> ParseScenarioKind(const std::string& name) {
  for (std::size_t k = 0; k < std::size(kScenarioKindNames); ++k) {
    if (name == kScenarioKindNames[k]) return static_cast<ScenarioKind>(k);
  }
  return std::nullopt;
}

ScenarioKind KindOfEffects(std::size_t effects) {
  return effects == 0 ? ScenarioKind::kNone : effects == 1 ? ScenarioKind::kSingle : ScenarioKind::kPair;
}

}  // namespace edsp::gap
