#pragma once
// One channel of the model-predictive cueing (cueing/mpc_cueing.h): a
// translation of the platform, a rotation, or a translation with the
// rotation that tilts gravity into it (surge with pitch, sway with roll),
// each driven by its jerk, and what it makes the rider feel against what
// the vehicle would, through the vestibular models (cueing/vestibular.h).
//
// The state, in the platform's coordinates about the neutral pose:
//   p v a      the translation, its velocity and acceleration
//   θ ω α      the rotation (an Euler angle), its rate and acceleration
//   f_v w_v    the vehicle's specific force and angular velocity on this
//              channel, held over the horizon (no prediction beyond it)
//   x_o, x_c   the otoliths' and the canals' states driven by the
//              difference between the rider's and the vehicle's input:
//                d_f = a + lever·α + tilt·θ − (f_v − offset)
//                d_w = ω − w_v
// so a perceived error is C x: the models are linear, and perceiving the
// difference is the difference of the perceptions. Linearised about the
// neutral pose (small angles), the head `lever` above the platform.
//
// Every solve period the jerks over a horizon of fine then coarse
// intervals minimise Σ dt e^(−t/τ) (perceived errors in thresholds² plus
// the washout's penalties on p, v, a, θ, ω, α in their limits) and the
// terminal penalty, subject to
// every state's box at every interval's end and the jerks' box: a
// condensed QP in the jerks (cueing/dense_qp.h). The boxes are the
// channel's largest times its share (position, velocity, acceleration),
// which may change from solve to solve (cueing/mpc_limits.h); the
// penalties weigh each value over the box of the shares all channels have
// at once, so the cost stays as it was tuned. The first jerk is held
// at the setpoint rate until the next solve, so the acceleration is
// continuous and the jerk bounded by construction.

#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "edsp/cueing/dense_qp.h"
#include "edsp/cueing/vestibular.h"

namespace edsp {

struct MpcAxisBox {
  double position = 0.0, velocity = 0.0, acceleration = 0.0, jerk = 0.0;  // ± each
};

// The washout's penalties: each a weight on (value / its box)², beside the
// perceived errors' weight on (error / threshold)².
struct MpcPenalties {
  double perceived_force = 1.0;
  double perceived_rate = 1.0;
  double position = 0.3, velocity = 0.05, acceleration = 0.0, jerk = 1e-4;
  double terminal = 5.0;  // the last interval's position and velocity penalties, this many times
  // Each stage's cost weighed by e^(−t/τ) at t along the horizon, the
  // terminal penalty whole: the vehicle's input held over the horizon is a
  // guess that ages (0: every stage alike).
  double horizon_discount_s = 0.5;
};

struct MpcHorizon {
  double solve_period_s = 0.01;  // the first intervals: what is applied before the next solve
  int fine_intervals = 4;
  double coarse_interval_s = 0.075;
  int coarse_intervals = 12;
};

struct MpcChannelSetup {
  bool translation = false, rotation = false;
  bool otolith = false;            // perceived specific force in the cost (translation, or a tilt into it)
  bool canal = false;              // perceived angular velocity in the cost (rotation)
  double tilt_m_s2_per_rad = 0.0;  // specific force per rad of the rotation: −g pitch → fx, +g roll → fy
  double lever_m = 0.0;            // head translation per rad: +h pitch → x, −h roll → y
  double force_offset_m_s2 = 0.0;  // the vehicle's force at rest on this channel (g on fz)
  double force_threshold = 1.0, rate_threshold = 1.0;
  MpcAxisBox translation_box, rotation_box;  // at a share of 1
  // The shares the penalties are weighed at (position, velocity,
  // acceleration), and where the shares start.
  Eigen::Vector3d penalty_share = Eigen::Vector3d::Ones();
  MpcPenalties penalties;
  MpcHorizon horizon;
  VestibularParameters perception;
  double period_s = 1e-3;  // a Step
};

class MpcChannel {
 public:
  // Throws std::invalid_argument naming what is absurd (a box ≤ 0, a
  // period that does not divide the solve period, a horizon of no interval).
  explicit MpcChannel(const MpcChannelSetup& setup);

  // One setpoint period with the vehicle's newest force and rate on this
  // channel; solves first when one is due.
  void Step(double vehicle_force, double vehicle_rate);
  // Whether the next Step solves.
  bool SolvesNext() const { return step_ % steps_per_solve_ == 0; }
  // The share of the boxes the next solves keep to (position, velocity,
  // acceleration; each in [0, 1]): below what the plan holds (PlanShare),
  // the plan may have no way inside.
  void SetShare(const Eigen::Vector3d& share);
  const Eigen::Vector3d& share() const { return share_; }
  const Eigen::Vector3d& start_share() const { return setup_.penalty_share; }
  // The largest share of the boxes the state and the last solve's plan
  // reach, per kind.
  Eigen::Vector3d PlanShare() const;
  // At rest at neutral with the shares it started with, the next Step
  // solving from a cold start.
  void Reset();
  double translation_m() const { return x_(kP); }
  double rotation_rad() const { return x_(kTheta); }
  double translation_velocity() const { return x_(kV); }
  double rotation_rate() const { return x_(kOmega); }
  const Eigen::VectorXd& state() const { return x_; }
  // The last solve's figures, and how many solves so far stopped at the
  // iteration limit before the tolerance (their jerks clipped and applied).
  const DenseQpResult& last_solve() const;
  std::int64_t unconverged_solves() const { return unconverged_; }
  int variables() const;
  int constraints() const;
  // The last solve's problem whole, for checking the solver against another.
  struct Problem {
    Eigen::MatrixXd hessian, constraint;
    Eigen::VectorXd g, lower, upper;
  };
  Problem last_problem() const;

 private:
  // The state's layout (every channel has all of it; an axis it does not
  // move stays at zero): the otoliths' two states, then the canals' three.
  static constexpr int kP = 0, kV = 1, kA = 2, kTheta = 3, kOmega = 4, kAlpha = 5, kForce = 6, kRate = 7, kOtolith = 8,
                       kCanal = 10, kStates = 13;
  void Solve();

  MpcChannelSetup setup_;
  int nu_ = 0;  // jerks: the translation's, the rotation's
  int steps_per_solve_ = 1, step_ = 0;
  std::int64_t unconverged_ = 0;
  Eigen::MatrixXd a_step_, b_step_;  // one setpoint period
  Eigen::MatrixXd f_;                // g = f_ x0
  Eigen::MatrixXd state_rows_;       // the boxed states' predictions: rows · x0 + (rows of Γ) U
  Eigen::MatrixXd plan_rows_;        // those rows of Γ
  Eigen::VectorXd state_bound_;      // at a share of 1
  Eigen::VectorXi bound_kind_;       // 0 position, 1 velocity, 2 acceleration
  Eigen::VectorXi boxed_state_;      // the state each of an interval's rows bounds
  Eigen::Vector3d share_ = Eigen::Vector3d::Ones();
  Eigen::VectorXd plan_;  // the boxed states along the last solve's plan
  Eigen::VectorXd jerk_bound_;
  Eigen::VectorXd x_, u_;
  Eigen::VectorXd g_, lower_, upper_;
  std::unique_ptr<DenseQp> qp_;
};

}  // namespace edsp
