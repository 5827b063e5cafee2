#pragma once
// The second derivative from three samples, the one formula every consumer
// of an acceleration from positions shares (the diagnosis's design, the
// calibration's point A, the rig's swaying mount).

namespace edsp {

// At t, from samples at t − h1, t and t + h2 (h1, h2 > 0): exact for a
// quadratic whatever the spacing. A live tracker's stamps jitter by a
// fraction of the spacing (the rig's cycle wakes late by up to a few
// hundred µs); the evenly spaced formula made that jitter accelerations as
// large as the motion's own (1 m/s² at 0.25 m/s from 0.2 ms on a 10 ms
// spacing).
template <typename V>
V SecondDerivative(const V& before, const V& at, const V& after, double h1, double h2) {
  return (2.0 / (h1 + h2)) * ((after - at) / h2 - (at - before) / h1);
}

}  // namespace edsp
