#include "edsp/cueing/mpc_channel.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "edsp/cueing/linear_filter.h"

namespace edsp {
namespace {

// τa so long that the canal model is τL s / ((τL s + 1)(τS s + 1)) over any horizon.
constexpr double kCanalAdaptationLeftOut_s = 1e6;

void CheckBox(const MpcAxisBox& box, const char* what) {
  for (double v : {box.position, box.velocity, box.acceleration, box.jerk}) {
    if (!std::isfinite(v) || v <= 0.0) {
      throw std::invalid_argument(fmt::format("MPC {} box: {} (every limit must be finite and > 0)", what, v));
    }
  }
}

// The intervals of the horizon, first to last.
std::vector<double> Intervals(const MpcHorizon& h) {
  std::vector<double> dt(static_cast<std::size_t>(h.fine_intervals), h.solve_period_s);
  dt.insert(dt.end(), static_cast<std::size_t>(h.coarse_intervals), h.coarse_interval_s);
  return dt;
}

}  // namespace

MpcChannel::MpcChannel(const MpcChannelSetup& setup) : setup_(setup) {
  const MpcHorizon& h = setup.horizon;
  if (!setup.translation && !setup.rotation) throw std::invalid_argument("MPC channel: moves no axis");
  if (setup.translation) CheckBox(setup.translation_box, "translation");
  if (setup.rotation) CheckBox(setup.rotation_box, "rotation");
  if (!(setup.period_s > 0.0) || !(h.solve_period_s >= setup.period_s) || h.fine_intervals < 1 ||
      h.coarse_intervals < 0 || !(h.coarse_interval_s > 0.0)) {
    throw std::invalid_argument(
        fmt::format("MPC horizon: solve period {} s over setpoint period {} s, {} fine and {} coarse intervals of {} s",
                    h.solve_period_s, setup.period_s, h.fine_intervals, h.coarse_intervals, h.coarse_interval_s));
  }
  if (!(setup.penalty_share.minCoeff() > 0.0 && setup.penalty_share.maxCoeff() <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("MPC channel: shares {} {} {} (each must be in (0, 1]: the legs leave no room)",
                    setup.penalty_share(0), setup.penalty_share(1), setup.penalty_share(2)));
  }
  const double ratio = h.solve_period_s / setup.period_s;
  steps_per_solve_ = static_cast<int>(std::lround(ratio));
  if (std::fabs(ratio - steps_per_solve_) > 1e-9 * ratio) {
    throw std::invalid_argument(
        fmt::format("MPC: the solve period {} s is not a whole number of setpoint periods ({} s)", h.solve_period_s,
                    setup.period_s));
  }

  // The continuous plant: two triple integrators, the held inputs, and the
  // vestibular models of the difference.
  nu_ = (setup.translation ? 1 : 0) + (setup.rotation ? 1 : 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(kStates, kStates), b = Eigen::MatrixXd::Zero(kStates, nu_);
  a(kP, kV) = a(kV, kA) = a(kTheta, kOmega) = a(kOmega, kAlpha) = 1.0;
  int input = 0;
  if (setup.translation) b(kA, input++) = 1.0;
  if (setup.rotation) b(kAlpha, input++) = 1.0;
  // d_f and d_w as rows on the state.
  Eigen::RowVectorXd force_difference = Eigen::RowVectorXd::Zero(kStates), rate_difference = force_difference;
  force_difference(kA) = setup.translation ? 1.0 : 0.0;
  force_difference(kAlpha) = setup.lever_m;
  force_difference(kTheta) = setup.tilt_m_s2_per_rad;
  force_difference(kForce) = -1.0;
  rate_difference(kOmega) = setup.rotation ? 1.0 : 0.0;
  rate_difference(kRate) = -1.0;
  const StateSpace otolith = Realise(OtolithTransferFunction(setup.perception.otolith));
  // The canals' adaptation (τa, tens of seconds) is left out of the
  // prediction: over a horizon of a second its state is a constant offset,
  // which the platform would otherwise chase away from neutral for minutes
  // after every rotation.
  CanalParameters canal_predicted = setup.perception.canal;
  canal_predicted.tau_a_s = kCanalAdaptationLeftOut_s;
  const StateSpace canal = Realise(CanalTransferFunction(canal_predicted));
  a.block(kOtolith, kOtolith, 2, 2) = otolith.a;
  a.block(kOtolith, 0, 2, kStates) += otolith.b * force_difference;
  a.block(kCanal, kCanal, 3, 3) = canal.a;
  a.block(kCanal, 0, 3, kStates) += canal.b * rate_difference;

  // What the cost weighs, a row each, the weight of each row, and whether
  // it is a washout penalty (terminal_penalty times at the horizon's end).
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> weights;
  std::vector<bool> terminal;
  const auto weigh = [&](Eigen::RowVectorXd row, double weight, bool washout) {
    if (weight <= 0.0) return;
    rows.push_back(std::move(row));
    weights.push_back(weight);
    terminal.push_back(washout);
  };
  const MpcPenalties& w = setup.penalties;
  if (setup.otolith) {
    Eigen::RowVectorXd row = otolith.d * force_difference;
    row.segment(kOtolith, 2) += otolith.c;
    weigh(row, w.perceived_force / (setup.force_threshold * setup.force_threshold), false);
  }
  if (setup.canal) {
    Eigen::RowVectorXd row = canal.d * rate_difference;
    row.segment(kCanal, 3) += canal.c;
    weigh(row, w.perceived_rate / (setup.rate_threshold * setup.rate_threshold), false);
  }
  const auto unit = [](int state) {
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(kStates);
    row(state) = 1.0;
    return row;
  };
  std::vector<std::pair<int, double>> boxed;  // state, its bound
  const Eigen::Vector3d& at = setup.penalty_share;
  const auto axis = [&](int first, const MpcAxisBox& box) {
    weigh(unit(first), w.position / std::pow(at(0) * box.position, 2), true);
    weigh(unit(first + 1), w.velocity / std::pow(at(1) * box.velocity, 2), true);
    weigh(unit(first + 2), w.acceleration / std::pow(at(2) * box.acceleration, 2), false);
    boxed.emplace_back(first, box.position);
    boxed.emplace_back(first + 1, box.velocity);
    boxed.emplace_back(first + 2, box.acceleration);
  };
  if (setup.translation) axis(kP, setup.translation_box);
  if (setup.rotation) axis(kTheta, setup.rotation_box);
  Eigen::MatrixXd cost_rows(static_cast<Eigen::Index>(rows.size()), kStates);
  for (std::size_t r = 0; r < rows.size(); ++r) cost_rows.row(static_cast<Eigen::Index>(r)) = rows[r];
  jerk_bound_ = Eigen::VectorXd(nu_);
  input = 0;
  if (setup.translation) jerk_bound_(input++) = setup.translation_box.jerk;
  if (setup.rotation) jerk_bound_(input++) = setup.rotation_box.jerk;

  // Condensed: the states at every interval's end from x0 and the jerks.
  const std::vector<double> dt = Intervals(h);
  const auto n = static_cast<Eigen::Index>(dt.size());
  const Eigen::Index nx = kStates, nu = nu_;
  Eigen::MatrixXd phi(n * nx, nx), gamma = Eigen::MatrixXd::Zero(n * nx, n * nu);
  Eigen::MatrixXd q_bar = Eigen::MatrixXd::Zero(n * nx, n * nx), r_bar = Eigen::MatrixXd::Zero(n * nu, n * nu);
  Eigen::MatrixXd previous = Eigen::MatrixXd::Identity(nx, nx);
  double interval_end_s = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    interval_end_s += dt[static_cast<std::size_t>(k)];
    // The vehicle's input held this far ahead is a guess that ages: each
    // stage weighs less the later it comes; the horizon's end, where the
    // washout is asked for, keeps its whole weight.
    const double stage_weight = w.horizon_discount_s > 0.0 ? std::exp(-interval_end_s / w.horizon_discount_s) : 1.0;
    const HeldSystem held = ZeroOrderHold(a, b, dt[static_cast<std::size_t>(k)]);
    phi.block(k * nx, 0, nx, nx) = held.ad * previous;
    previous = phi.block(k * nx, 0, nx, nx);
    if (k > 0) gamma.block(k * nx, 0, nx, k * nu) = held.ad * gamma.block((k - 1) * nx, 0, nx, k * nu);
    gamma.block(k * nx, k * nu, nx, nu) = held.bd;
    Eigen::VectorXd weight(static_cast<Eigen::Index>(weights.size()));
    for (std::size_t r = 0; r < weights.size(); ++r) {
      weight(static_cast<Eigen::Index>(r)) = weights[r] * (k + 1 == n && terminal[r] ? w.terminal : stage_weight);
    }
    q_bar.block(k * nx, k * nx, nx, nx) =
        dt[static_cast<std::size_t>(k)] * cost_rows.transpose() * weight.asDiagonal() * cost_rows;
    for (Eigen::Index i = 0; i < nu; ++i) {
      r_bar(k * nu + i, k * nu + i) = dt[static_cast<std::size_t>(k)] * w.jerk / (jerk_bound_(i) * jerk_bound_(i));
    }
  }
  // In jerks over their bounds (each variable in [−1, 1]): the solver's
  // steps then weigh every input alike.
  Eigen::VectorXd scale(n * nu);
  for (Eigen::Index k = 0; k < n; ++k) scale.segment(k * nu, nu) = jerk_bound_;
  gamma = gamma * scale.asDiagonal();
  r_bar = scale.asDiagonal() * r_bar * scale.asDiagonal();
  const Eigen::MatrixXd hessian = 2.0 * (gamma.transpose() * q_bar * gamma + r_bar);
  f_ = 2.0 * gamma.transpose() * q_bar * phi;

  // Constraints: each boxed state at each interval's end, then the jerks.
  const auto boxes = static_cast<Eigen::Index>(boxed.size());
  Eigen::MatrixXd selection = Eigen::MatrixXd::Zero(n * boxes, n * nx);
  state_bound_ = Eigen::VectorXd(n * boxes);
  bound_kind_ = Eigen::VectorXi(n * boxes);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index s = 0; s < boxes; ++s) {
      selection(k * boxes + s, k * nx + boxed[static_cast<std::size_t>(s)].first) = 1.0;
      state_bound_(k * boxes + s) = boxed[static_cast<std::size_t>(s)].second;
      bound_kind_(k * boxes + s) = static_cast<int>(s % 3);  // each axis boxes p, v, a in turn
    }
  }
  boxed_state_ = Eigen::VectorXi(boxes);
  for (Eigen::Index s = 0; s < boxes; ++s) boxed_state_(s) = boxed[static_cast<std::size_t>(s)].first;
  state_rows_ = selection * phi;
  plan_rows_ = selection * gamma;
  plan_ = Eigen::VectorXd::Zero(n * boxes);
  Eigen::MatrixXd constraint(n * boxes + n * nu, n * nu);
  constraint << plan_rows_, Eigen::MatrixXd::Identity(n * nu, n * nu);
  lower_ = Eigen::VectorXd(constraint.rows());
  upper_ = Eigen::VectorXd(constraint.rows());
  for (Eigen::Index k = 0; k < n; ++k) {
    upper_.segment(n * boxes + k * nu, nu).setOnes();
    lower_.segment(n * boxes + k * nu, nu).setConstant(-1.0);
  }
  // A cue needs no more digits than the legs can follow: residuals of 1e-5
  // of the data's scale, and a bounded number of iterations per solve.
  DenseQpSettings settings;
  settings.eps_abs = settings.eps_rel = 1e-5;
  settings.max_iterations = 300;
  qp_ = std::make_unique<DenseQp>(hessian, constraint, settings);

  const HeldSystem step = ZeroOrderHold(a, b, setup.period_s);
  a_step_ = step.ad;
  b_step_ = step.bd;
  x_ = Eigen::VectorXd::Zero(kStates);
  u_ = Eigen::VectorXd::Zero(nu_);
  SetShare(setup.penalty_share);
}

void MpcChannel::Solve() {
  const Eigen::VectorXd offset = state_rows_ * x_;
  const Eigen::Index boxes = state_bound_.size();
  for (Eigen::Index r = 0; r < boxes; ++r) {
    const double bound = share_(bound_kind_(r)) * state_bound_(r);
    upper_(r) = bound - offset(r);
    lower_(r) = -bound - offset(r);
  }
  g_ = f_ * x_;
  const DenseQpResult& result = qp_->Solve(g_, lower_, upper_);
  if (!result.converged) ++unconverged_;
  const Eigen::VectorXd jerks = result.x.cwiseMax(-1.0).cwiseMin(1.0);
  plan_ = plan_rows_ * jerks + offset;
  u_ = jerks.head(nu_).cwiseProduct(jerk_bound_);
}

void MpcChannel::SetShare(const Eigen::Vector3d& share) { share_ = share.cwiseMax(0.0).cwiseMin(1.0); }

Eigen::Vector3d MpcChannel::PlanShare() const {
  Eigen::Vector3d held = Eigen::Vector3d::Zero();
  for (Eigen::Index r = 0; r < plan_.size(); ++r) {
    const int kind = bound_kind_(r);
    held(kind) = std::max(held(kind), std::fabs(plan_(r)) / state_bound_(r));
  }
  for (Eigen::Index s = 0; s < boxed_state_.size(); ++s) {  // the state now, where the plan goes on from
    const int kind = bound_kind_(s);
    held(kind) = std::max(held(kind), std::fabs(x_(boxed_state_(s))) / state_bound_(s));
  }
  return held;
}

void MpcChannel::Reset() {
  x_.setZero();
  u_.setZero();
  plan_.setZero();
  share_ = setup_.penalty_share;
  step_ = 0;
  qp_->Reset();
}

void MpcChannel::Step(double vehicle_force, double vehicle_rate) {
  x_(kForce) = vehicle_force - setup_.force_offset_m_s2;
  x_(kRate) = vehicle_rate;
  if (step_++ % steps_per_solve_ == 0) Solve();
  x_ = a_step_ * x_ + b_step_ * u_;
}

const DenseQpResult& MpcChannel::last_solve() const { return qp_->last(); }

MpcChannel::Problem MpcChannel::last_problem() const {
  return {qp_->hessian(), qp_->constraint_matrix(), g_, lower_, upper_};
}

int MpcChannel::variables() const { return qp_->variables(); }
int MpcChannel::constraints() const { return qp_->constraints(); }

}  // namespace edsp
