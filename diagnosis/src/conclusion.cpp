#include "edsp/diagnosis/conclusion.h"

#include <cstddef>
#include <iterator>

namespace edsp::gap {

namespace {

// In the enum's order (conclusions are written, never read back).
constexpr const char* kConclusionNames[] = {"effects", "none", "unknown", "effects+unknown"};
static_assert(std::size(kConclusionNames) == static_cast<std::size_t>(Conclusion::kEffectsAndUnknown) + 1,
              "a name per conclusion");

bool NamesEffects(Conclusion c) { return c == Conclusion::kEffects || c == Conclusion::kEffectsAndUnknown; }

}  // namespace

const char* ConclusionName(Conclusion conclusion) { return kConclusionNames[static_cast<std::size_t>(conclusion)]; }

Conclusion Conclude(bool effects, bool unknown) {
  if (unknown) return effects ? Conclusion::kEffectsAndUnknown : Conclusion::kUnknown;
  return effects ? Conclusion::kEffects : Conclusion::kNone;
}

bool NamesUnknown(Conclusion c) { return c == Conclusion::kUnknown || c == Conclusion::kEffectsAndUnknown; }

Conclusion WithUnknown(Conclusion c) { return Conclude(NamesEffects(c), true); }

}  // namespace edsp::gap
