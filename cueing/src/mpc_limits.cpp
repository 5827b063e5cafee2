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

// The largest λ ≤ 1 with Σ_j L_ij λ b_j ≤ budget_i for every leg.
double Scale(const Matrix6& slope, const Vector6& wanted, const Vector6& budget) {
  const Vector6 used = slope * wanted;
  double scale = 1.0;
  for (int i = 0; i < 6; ++i) scale = std::min(scale, used(i) > 0.0 ? budget(i) / used(i) : 1.0);
  return std::max(scale, 0.0);
}

bool CornersReachable(const PlatformModel& model, const Pose& neutral, const Vector6& half) {
  for (const Vector6& q : BoxSamples(half)) {
    const Pose pose = Displaced(neutral, q);
    if (!CheckLegs(model, model.Solve(pose)).ok() || !CheckConditioning(model, pose).ok()) return false;
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

MpcAxisLimits DeriveMpcLimits(const PlatformModel& model, const Pose& neutral, const MpcAxisLimits& wanted,
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

  MpcAxisLimits limits;
  const std::vector<Vector6> samples = BoxSamples(wanted.position);
  const Matrix6 slope = SlopeBound(model, neutral, samples);
  limits.position_scale = Scale(slope, wanted.position, (1.0 - margin) * room);
  while (limits.position_scale > 1e-3 && !CornersReachable(model, neutral, limits.position_scale * wanted.position)) {
    limits.position_scale *= kShrink;
  }
  if (!CornersReachable(model, neutral, limits.position_scale * wanted.position)) {
    throw std::invalid_argument("[mpc]: no box about the neutral pose keeps its corners inside the workspace");
  }
  limits.position = limits.position_scale * wanted.position;
  const Vector6 speed_budget = Vector6::Constant((1.0 - margin) * legs.leg_speed_max_m_s);
  limits.velocity_scale = Scale(slope, wanted.velocity, speed_budget);
  limits.velocity = limits.velocity_scale * wanted.velocity;
  const Vector6 curvature = CurvatureBound(model, neutral, BoxSamples(limits.position), limits.velocity);
  const Vector6 accel_budget = (Vector6::Constant((1.0 - margin) * accel_max) - curvature).cwiseMax(0.0);
  limits.acceleration_scale = Scale(slope, wanted.acceleration, accel_budget);
  limits.acceleration = limits.acceleration_scale * wanted.acceleration;
  return limits;
}

}  // namespace edsp
