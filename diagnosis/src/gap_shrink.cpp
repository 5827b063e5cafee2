#include "edsp/diagnosis/gap_shrink.h"

#include "edsp/diagnosis/percent_text.h"

namespace edsp::gap {

std::string GapShrinkText(double before_rms_m, double noise_floor_rms_m, double gap_shrink) {
  if (before_rms_m <= noise_floor_rms_m) return "no gap above it";
  return Percent(gap_shrink) + " of the gap above it closed";
}

}  // namespace edsp::gap
