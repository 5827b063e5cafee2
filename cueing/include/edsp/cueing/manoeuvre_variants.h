#pragma once
// Manoeuvres no cueing was tuned on: each shipped manoeuvre drawn again
// with every amplitude scaled by one factor (0.6–1.4: a gentler or harder
// driver) and every pulse's hold shortened (0.6–1.0 of it, so it still ends
// inside the file's duration), from a seed. The bench scores the cueing on
// them beside the shipped ones (docs/cueing.md, "Bench"), so a setting
// chosen on the seven files shows whether it carries to their neighbours.

#include <cstdint>
#include <vector>

#include "edsp/cueing/manoeuvre.h"

namespace edsp {

struct ManoeuvreVariation {
  double amplitude_min = 0.6, amplitude_max = 1.4;  // one factor per variant, on every amplitude
  double hold_min = 0.6, hold_max = 1.0;            // one factor per variant, on every pulse's hold
};

// `count` variants of `manoeuvre`, named <name>_v0, <name>_v1, …; the same
// seed draws the same variants. Throws std::invalid_argument for a
// variation outside (0, 2] or min above max.
std::vector<Manoeuvre> ManoeuvreVariants(const Manoeuvre& manoeuvre, int count, std::uint64_t seed,
                                         const ManoeuvreVariation& variation = {});

}  // namespace edsp
