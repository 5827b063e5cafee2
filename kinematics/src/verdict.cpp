#include "edsp/kinematics/verdict.h"

#include <cstddef>
#include <iterator>

namespace edsp::calibration {

namespace {

// In the enum's order: the one place the names are spelt, so that printing
// and parsing cannot disagree.
constexpr const char* kNames[] = {"identified", "ambiguous", "rejected"};
static_assert(std::size(kNames) == static_cast<std::size_t>(Verdict::kRejected) + 1, "a name per verdict");

}  // namespace

const char* VerdictName(Verdict verdict) { return kNames[static_cast<std::size_t>(verdict)]; }

std::optional<Verdict> VerdictFromName(std::string_view name) {
  for (std::size_t k = 0; k < std::size(kNames); ++k) {
    if (name == kNames[k]) return static_cast<Verdict>(k);
  }
  return std::nullopt;
}

}  // namespace edsp::calibration
