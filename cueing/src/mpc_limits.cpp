#include "edsp/cueing/mpc_limits.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "edsp/kinematics/workspace.h"

namespace edsp {
namespace {

constexpr const char* kAxes[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
constexpr int kRandomPoints = 200;
constexpr double kWiden = 1.05;  // on the sampled largest slopes and curvatures
constexpr double kShrink = 0.9;  // per step while a corner fails the joint or conditioning check
constexpr double kDerivativeStep = 1e-6;

Pose Displaced(const Pose& neutral, const Vector6& q) { return Pose::FromVector(neutral.ToVector() + q); }

// Every sign combination of `half` (the 64 corners), the centre, and random points inside.
std::vector<Vector6> BoxSamples(const Vector6& half) {
  std::vector<Vector6> points;
  for (int corner = 0; corner < 64; ++corner) {
    Vector6 q;
    for (int j = 0; j < 6; ++j) q(j) = ((corner >> j) & 1) != 0 ? half(j) : -half(j);
    points.push_back(q);
  }
  points.push_back(Vector6::Zero());
  std::mt19937_64 random(20261206);  // fixed: the same box from the same config
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int k = 0; k < kRandomPoints; ++k) {
    Vector6 q;
    for (int j = 0; j < 6; ++j) q(j) = unit(random) * half(j);
    points.push_back(q);
  }
  return points;
}

// L_ij: the largest |∂l_i/∂q_j| over the samples, widened.
Matrix6 SlopeBound(const PlatformModel& model, const Pose& neutral, const std::vector<Vector6>& samples) {
  Matrix6 bound = Matrix6::Zero();
  for (const Vector6& q : samples) {
    for (int j = 0; j < 6; ++j) {
      Vector6 step = Vector6::Zero();
      step(j) = kDerivativeStep;
      const Vector6 slope =
          (model.LegLengths(Displaced(neutral, q + step)) - model.LegLengths(Displaced(neutral, q - step))) /
          (2.0 * kDerivativeStep);
      bound.col(j) = bound.col(j).cwiseMax(slope.cwiseAbs());
    }
  }
  return kWiden * bound;
}

// The largest |q̇ᵀ ∇²l_i q̇| per leg over the samples and the velocity box's corners.
Vector6 CurvatureBound(const PlatformModel& model, const Pose& neutral, const std::vector<Vector6>& samples,
                       const Vector6& velocity) {
  Vector6 bound = Vector6::Zero();
  const double h = 1e-3;
  for (const Vector6& q : samples) {
    const Vector6 at = model.LegLengths(Displaced(neutral, q));
    for (int corner = 0; corner < 64; ++corner) {
      Vector6 v;
      for (int j = 0; j < 6; ++j) v(j) = ((corner >> j) & 1) != 0 ? velocity(j) : -velocity(j);
      const Vector6 second = (model.LegLengths(Displaced(neutral, q + h * v)) - 2.0 * at +
                              model.LegLengths(Displaced(neutral, q - h * v))) /
                             (h * h);
      bound = bound.cwiseMax(second.cwiseAbs());
    }
  }
  return kWiden * bound;
}

// Per channel, per leg: Σ_{j in c} slope_ij wanted_j.
Eigen::Matrix<double, kMpcChannels, 6> ChannelUse(const Matrix6& slope, const Vector6& wanted) {
  Eigen::Matrix<double, kMpcChannels, 6> use = Eigen::Matrix<double, kMpcChannels, 6>::Zero();
  for (int j = 0; j < 6; ++j) use.row(kMpcChannelOfAxis[j]) += (slope.col(j) * wanted(j)).transpose();
  return use;
}

MpcLegShare Share(const Matrix6& slope, const Vector6& wanted, const Vector6& budget) {
  MpcLegShare share;
  share.use = ChannelUse(slope, wanted);
  share.budget = budget.cwiseMax(0.0);
  for (int c = 0; c < kMpcChannels; ++c) {
    double most = 1.0;
    for (int i = 0; i < 6; ++i) {
      if (share.use(c, i) > 0.0) most = std::min(most, share.budget(i) / share.use(c, i));
    }
    share.most(c) = std::max(most, 0.0);
  }
  return share;
}

// Per axis: the wanted value times its channel's λ.
Vector6 PerAxis(const Vector6& wanted, const MpcChannelVector& lambda) {
  Vector6 v;
  for (int j = 0; j < 6; ++j) v(j) = wanted(j) * lambda(kMpcChannelOfAxis[j]);
  return v;
}

// The joint angles and the conditioning (the strokes are the shares' to keep).
bool CornersReachable(const PlatformModel& model, const Pose& neutral, const Vector6& half) {
  for (const Vector6& q : BoxSamples(half)) {
    const Pose pose = Displaced(neutral, q);
    if (!CheckJointAngles(model, model.Solve(pose)).ok() || !CheckConditioning(model, pose).ok()) return false;
  }
  return true;
}

void CheckWanted(const Vector6& v, const char* what) {
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(v(j)) || v(j) <= 0.0) {
      throw std::invalid_argument(fmt::format("[mpc] {} of {}: {} (must be finite and > 0)", what, kAxes[j], v(j)));
    }
  }
}

}  // namespace

std::string MpcAxisLimits::Describe() const {
  std::string text;
  for (int j = 0; j < 6; ++j) {
    const char* unit = j < 3 ? "m" : "rad";
    text += fmt::format("{}{} ±{:.4g} {}, ±{:.4g} {}/s, ±{:.4g} {}/s^2", j == 0 ? "" : "; ", kAxes[j], position(j),
                        unit, velocity(j), unit, acceleration(j), unit);
  }
  return text;
}

MpcChannelVector MpcLegShare::Allocate(const MpcChannelVector& committed, const MpcChannelVector& demand) const {
  const MpcChannelVector held = committed.cwiseMax(0.0).cwiseMin(most);
  const double top = demand.cwiseMax(0.0).maxCoeff();
  const MpcChannelVector weight = top > 0.0 ? MpcChannelVector(demand.cwiseMax(0.0) / top) : MpcChannelVector::Ones();
  const MpcChannelVector wish = weight.cwiseProduct(most - held);
  double s = 1.0;
  for (int i = 0; i < 6; ++i) {
    const double left = budget(i) - held.dot(use.col(i));
    const double asked = wish.dot(use.col(i));
    if (asked > 0.0) s = std::min(s, left / asked);
  }
  return held + std::max(s, 0.0) * wish;
}

double MpcLegShare::Load(const MpcChannelVector& lambda) const {
  double load = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double used = lambda.dot(use.col(i));
    load = std::max(load, budget(i) > 0.0 ? used / budget(i) : (used > 0.0 ? 1e300 : 0.0));
  }
  return load;
}

MpcAxisLimits MpcLegRoom::Box(const MpcChannelVector& position_lambda, const MpcChannelVector& velocity_lambda,
                              const MpcChannelVector& acceleration_lambda) const {
  MpcAxisLimits box;
  box.position = PerAxis(wanted.position, position_lambda);
  box.velocity = PerAxis(wanted.velocity, velocity_lambda);
  box.acceleration = PerAxis(wanted.acceleration, acceleration_lambda);
  box.position_scale = position_lambda.minCoeff();
  box.velocity_scale = velocity_lambda.minCoeff();
  box.acceleration_scale = acceleration_lambda.minCoeff();
  return box;
}

MpcAxisLimits MpcLegRoom::AllAtOnce() const {
  const MpcChannelVector none = MpcChannelVector::Zero(), alike = MpcChannelVector::Ones();
  return Box(position.Allocate(none, alike), velocity.Allocate(none, alike), acceleration.Allocate(none, alike));
}

MpcLegRoom DeriveMpcLegRoom(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
                            double margin) {
  CheckWanted(wanted.position, "position_max");
  CheckWanted(wanted.velocity, "velocity_max");
  CheckWanted(wanted.acceleration, "acceleration_max");
  if (!(margin >= 0.0 && margin <= 0.5)) {
    throw std::invalid_argument(fmt::format("[mpc] leg_margin = {}: must be in [0, 0.5]", margin));
  }
  if (!CheckLegs(model, model.Solve(neutral)).ok()) {
    throw std::invalid_argument("[mpc]: the neutral pose is outside the workspace");
  }
  const WorkspaceLimits& legs = model.config().limits;
  const double accel_max = model.config().motion.leg_accel_max_m_s2;
  const Vector6 home = model.LegLengths(neutral);
  Vector6 room;
  for (int i = 0; i < 6; ++i) room(i) = std::min(home(i) - legs.leg_min_m, legs.leg_max_m - home(i));

  MpcLegRoom result;
  result.wanted = wanted;
  Matrix6 slope;
  // The slopes over the box of every channel's largest position at once,
  // whose corners must keep the joints and the conditioning.
  for (;;) {
    slope = SlopeBound(model, neutral, BoxSamples(result.wanted.position));
    result.position = Share(slope, result.wanted.position, (1.0 - margin) * room);
    const Vector6 largest = PerAxis(result.wanted.position, result.position.most);
    if (CornersReachable(model, neutral, largest)) break;
    result.wanted.position *= kShrink;
    if (result.wanted.position.maxCoeff() < 1e-3 * wanted.position.maxCoeff()) {
      throw std::invalid_argument("[mpc]: no box about the neutral pose keeps its corners inside the workspace");
    }
  }
  result.velocity = Share(slope, wanted.velocity, Vector6::Constant((1.0 - margin) * legs.leg_speed_max_m_s));
  const Vector6 fastest = PerAxis(wanted.velocity, result.velocity.most);
  const Vector6 widest = PerAxis(result.wanted.position, result.position.most);
  const Vector6 curvature = CurvatureBound(model, neutral, BoxSamples(widest), fastest);
  result.acceleration = Share(slope, wanted.acceleration, Vector6::Constant((1.0 - margin) * accel_max) - curvature);
  return result;
}

MpcAxisLimits DeriveMpcLimits(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
                              double margin) {
  return DeriveMpcLegRoom(model, neutral, wanted, margin).AllAtOnce();
}

}  // namespace edsp
