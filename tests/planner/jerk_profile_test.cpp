// The timing of moves and of their halts: every limit held (checked by
// finite differences of the positions alone), the ends at rest, and the
// durations and distances the closed forms give.
#include "edsp/planner/jerk_profile.h"

#include <gtest/gtest.h>

#include <cmath>

namespace edsp {
namespace {

struct Peaks {
  double v = 0.0, a = 0.0, j = 0.0;
};

// Peak |velocity|, |acceleration|, |jerk| from positions sampled every dt.
Peaks Differenced(const JerkProfile& p, double dt) {
  Peaks peaks;
  double x0 = p.At(0.0).position, x1 = p.At(dt).position, x2 = p.At(2 * dt).position;
  double a_before = (x2 - 2 * x1 + x0) / (dt * dt);
  peaks.v = std::abs(x1 - x0) / dt;
  for (double t = 3 * dt; t <= p.duration_s() + 3 * dt; t += dt) {
    const double x3 = p.At(t).position;
    const double a = (x3 - 2 * x2 + x1) / (dt * dt);
    peaks.v = std::max(peaks.v, std::abs(x3 - x2) / dt);
    peaks.a = std::max(peaks.a, std::abs(a));
    peaks.j = std::max(peaks.j, std::abs(a - a_before) / dt);
    x0 = x1, x1 = x2, x2 = x3, a_before = a;
  }
  return peaks;
}

TEST(JerkProfile, RestToRestKeepsEveryLimitAndEndsAtRestOnTheDistance) {
  const ScalarLimits l{0.1, 0.5, 5.0};
  for (double h : {1e-6, 1e-3, 0.01, 0.05, 0.3, 2.0}) {
    const JerkProfile p = JerkProfile::RestToRest(h, l);
    const ScalarState end = p.end();
    EXPECT_NEAR(end.position, h, 1e-12 + 1e-12 * h) << h;
    EXPECT_NEAR(end.velocity, 0.0, 1e-12) << h;
    EXPECT_NEAR(end.acceleration, 0.0, 1e-9) << h;
    const Peaks peaks = Differenced(p, 1e-4);
    EXPECT_LE(peaks.v, l.velocity * 1.0001) << h;
    EXPECT_LE(peaks.a, l.acceleration * 1.01) << h;
    EXPECT_LE(peaks.j, l.jerk * 1.05) << h;
  }
}

TEST(JerkProfile, ALongMoveTakesTheClosedFormTime) {
  // Cruising: T = h/v + v/a + a/j (acceleration and jerk limits both reached).
  const ScalarLimits l{0.1, 0.5, 5.0};
  EXPECT_NEAR(JerkProfile::RestToRest(1.0, l).duration_s(), 1.0 / 0.1 + 0.1 / 0.5 + 0.5 / 5.0, 1e-12);
  // Too short to reach either: T = 4·(h/2j)^(1/3).
  EXPECT_NEAR(JerkProfile::RestToRest(1e-6, l).duration_s(), 4.0 * std::cbrt(1e-6 / 10.0), 1e-12);
}

TEST(JerkProfile, AStopFromCruiseTravelsVSquaredOverTwoAPlusTheRamps) {
  const double v = 0.1, a = 0.5, j = 5.0;
  const JerkProfile stop = JerkProfile::StopFrom({0.2, v, 0.0}, a, j);
  EXPECT_NEAR(stop.end().position - 0.2, v * v / (2 * a) + v * a / (2 * j), 1e-12);
  EXPECT_NEAR(stop.end().velocity, 0.0, 1e-12);
  EXPECT_NEAR(stop.end().acceleration, 0.0, 1e-12);
  const Peaks peaks = Differenced(stop, 1e-4);
  EXPECT_LE(peaks.a, a * 1.01);
  EXPECT_LE(peaks.j, j * 1.05);
}

TEST(JerkProfile, AStopFromAnyStateOfAMoveEndsAtRestWithoutReversing) {
  const ScalarLimits l{0.1, 0.5, 5.0};
  const JerkProfile move = JerkProfile::RestToRest(0.05, l);
  for (double t = 0.0; t <= move.duration_s(); t += move.duration_s() / 97) {
    const ScalarState from = move.At(t);
    const JerkProfile stop = JerkProfile::StopFrom(from, l.acceleration, l.jerk);
    EXPECT_NEAR(stop.end().velocity, 0.0, 1e-9) << t;
    EXPECT_NEAR(stop.end().acceleration, 0.0, 1e-9) << t;
    double previous = from.position;
    for (double s = 0.0; s <= stop.duration_s(); s += 1e-4) {
      EXPECT_GE(stop.At(s).position, previous - 1e-12) << "reversed at " << t;
      previous = stop.At(s).position;
    }
  }
}

}  // namespace
}  // namespace edsp
