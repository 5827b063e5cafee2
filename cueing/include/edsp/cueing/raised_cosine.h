#pragma once
// 0 → 1 over x in [0, 1] as half a cosine: no step in value or slope at
// either end. What the manoeuvres' pulses and a lost input's fade follow.

#include <cmath>

#include "edsp/kinematics/types.h"

namespace edsp {

inline double RaisedCosine(double x) {
  if (!(x > 0.0)) return 0.0;  // NaN too
  if (x >= 1.0) return 1.0;
  return 0.5 * (1.0 - std::cos(kPi * x));
}

}  // namespace edsp
