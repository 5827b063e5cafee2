#pragma once
// A scalar motion u(t) made of pieces of constant jerk: the timing of every
// move (rest to rest, velocity, acceleration and jerk each within its limit:
// the double-S profile of Biagiotti & Melchiorri, "Trajectory Planning for
// Automatic Machines and Robots", §3.4) and of every halt and stop (from
// the state a motion is in to rest, as fast as the limits allow). Neither
// velocity nor acceleration ever steps. Written here because Debian 12
// packages no online trajectory generator (no Ruckig).

#include <utility>
#include <vector>

namespace edsp {

struct ScalarState {
  double position = 0.0;
  double velocity = 0.0;
  double acceleration = 0.0;
};

struct ScalarLimits {
  double velocity = 0.0;
  double acceleration = 0.0;
  double jerk = 0.0;
};

class JerkProfile {
 public:
  JerkProfile() = default;  // at rest at 0, duration 0

  // From rest at 0 to rest at `distance` (≥ 0) in the least time within
  // `limits` (each > 0).
  static JerkProfile RestToRest(double distance, const ScalarLimits& limits);
  // From `state` (velocity ≥ 0, acceleration ≥ −`acceleration`) to rest in
  // the least time with |acceleration| ≤ `acceleration` and |jerk| ≤ `jerk`.
  static JerkProfile StopFrom(const ScalarState& state, double acceleration, double jerk);
  // u = t from 0 to `duration` (a program's own clock: velocity 1).
  static JerkProfile Clock(double duration);

  double duration_s() const { return duration_s_; }
  // The state at t (clamped to [0, duration_s()]).
  ScalarState At(double t_s) const;
  ScalarState end() const { return At(duration_s_); }

 private:
  void Append(double duration_s, double jerk);

  ScalarState start_;
  std::vector<std::pair<double, double>> pieces_;  // (duration, jerk)
  std::vector<ScalarState> piece_start_;
  double duration_s_ = 0.0;
};

}  // namespace edsp
