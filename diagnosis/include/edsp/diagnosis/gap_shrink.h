#pragma once
// How far a model shrinks the residual: its RMS (Shrink), and the gap
// (GapShrink). The held-out gap is the platform's departure from the model
// beyond the tracker's own noise: on held-out runs the residual's mean
// square is the gap's plus the noise's (the noise is independent of every
// model), so the gap is √(rms² − floor²), and a model that leaves only the
// noise closes it.

#include <algorithm>
#include <cmath>
#include <string>

namespace edsp::gap {

// 1 − after/before of the residual's RMS (0 where there was none): bounded
// by the noise, 1 − floor/before however good the model.
inline double Shrink(double before_rms_m, double after_rms_m) {
  return before_rms_m > 0.0 ? 1.0 - after_rms_m / before_rms_m : 0.0;
}

// 1 − gap after / gap before: 1 where the residual is down to the floor (or
// below it, by the noise's own sampling), 0 where the gap is as it was,
// below 0 where a model makes it worse, and 0 where there was no gap above
// the floor. floor: the RMS of the 3-D noise, √3·σ per axis.
inline double GapShrink(double before_rms_m, double after_rms_m, double noise_floor_rms_m) {
  const double floor2 = noise_floor_rms_m * noise_floor_rms_m;
  const double gap_before = std::sqrt(std::max(0.0, before_rms_m * before_rms_m - floor2));
  const double gap_after = std::sqrt(std::max(0.0, after_rms_m * after_rms_m - floor2));
  return gap_before > 0.0 ? 1.0 - gap_after / gap_before : 0.0;
}

// For people: "96.4% of the gap above it closed", or "no gap above it"
// where the residual before was within the floor (GapShrink's 0 there is
// not a model that failed).
std::string GapShrinkText(double before_rms_m, double noise_floor_rms_m, double gap_shrink);

}  // namespace edsp::gap
