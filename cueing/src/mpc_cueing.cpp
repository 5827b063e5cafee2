#include "edsp/cueing/mpc_cueing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/cueing/vehicle_motion.h"
#include "edsp/kinematics/pose.h"

namespace edsp {
namespace {

// How much room a channel keeps beyond its plan, how fast its box may
// shrink onto it (a share of its wanted box per solve), and what it keeps
// however idle (of its share of all at once): room to start at once when
// its input comes and to wash out, and no box of zero, where every bound
// would be an equality.
constexpr double kPlanSlack = 1.05;
constexpr double kShrinkPerSolve = 0.02;
constexpr double kIdleReserve = 0.1;

enum Axis { kX = 0, kY = 1, kZ = 2, kRoll = 3, kPitch = 4, kYaw = 5 };

MpcAxisBox Box(const MpcAxisLimits& limits, const Vector6& jerk, int axis) {
  return {limits.position(axis), limits.velocity(axis), limits.acceleration(axis), jerk(axis)};
}

// Each channel's share when all fill theirs at once.
Eigen::Vector3d AllAtOnce(const MpcAxisLimits& at_once, const MpcAxisLimits& wanted, int axis) {
  return {at_once.position(axis) / wanted.position(axis), at_once.velocity(axis) / wanted.velocity(axis),
          at_once.acceleration(axis) / wanted.acceleration(axis)};
}

MpcChannelSetup Common(const VestibularParameters& perception, const MpcCueingParameters& p, double period_s) {
  MpcChannelSetup setup;
  setup.penalties = p.penalties;
  setup.horizon = p.horizon;
  setup.perception = perception;
  setup.period_s = period_s;
  return setup;
}

}  // namespace

void ValidateMpc(const MpcCueingParameters& p) {
  for (int axis = 0; axis < 6; ++axis) {
    if (!std::isfinite(p.jerk_max(axis)) || p.jerk_max(axis) <= 0.0) {
      throw std::invalid_argument(
          fmt::format("[mpc] jerk_max[{}] = {}: must be finite and > 0", axis, p.jerk_max(axis)));
    }
  }
  const MpcPenalties& w = p.penalties;
  for (double v : {w.perceived_force, w.perceived_rate, w.position, w.velocity, w.acceleration, w.jerk, w.terminal,
                   w.horizon_discount_s}) {
    if (!std::isfinite(v) || v < 0.0) throw std::invalid_argument(fmt::format("[mpc] a penalty is {}: must be ≥ 0", v));
  }
  if (!std::isfinite(p.demand_fade_s) || p.demand_fade_s <= 0.0) {
    throw std::invalid_argument(fmt::format("[mpc] demand_fade_s = {}: must be finite and > 0", p.demand_fade_s));
  }
  if (w.perceived_force + w.perceived_rate <= 0.0) {
    throw std::invalid_argument("[mpc] perceived_force and perceived_rate are both 0: the cueing would cue nothing");
  }
}

MpcCueing::MpcCueing(const PlatformModel& model, const Pose& neutral, const Vector3& head_in_platform_m,
                     const VestibularParameters& perception, const MpcCueingParameters& p, double period_s)
    : head_(head_in_platform_m), room_(DeriveMpcLegRoom(model, neutral, p.wanted, p.leg_margin)) {
  ValidateMpc(p);
  limits_ = room_.AllAtOnce();
  demand_decay_ = std::exp(-period_s / p.demand_fade_s);
  for (int k = 0; k < 6; ++k) thresholds_(k) = perception.Threshold(k);
  const MpcAxisLimits& whole = room_.wanted;
  const double h = head_in_platform_m.z();
  MpcChannelSetup surge = Common(perception, p, period_s);
  surge.translation = surge.rotation = surge.otolith = surge.canal = true;
  surge.tilt_m_s2_per_rad = -kStandardGravity_m_s2;
  surge.lever_m = h;
  surge.force_threshold = perception.Threshold(0);
  surge.rate_threshold = perception.Threshold(4);
  surge.translation_box = Box(whole, p.jerk_max, kX);
  surge.penalty_share = AllAtOnce(limits_, whole, kX);
  surge.rotation_box = Box(whole, p.jerk_max, kPitch);
  surge_ = std::make_unique<MpcChannel>(surge);

  MpcChannelSetup sway = surge;
  sway.tilt_m_s2_per_rad = kStandardGravity_m_s2;
  sway.lever_m = -h;
  sway.force_threshold = perception.Threshold(1);
  sway.rate_threshold = perception.Threshold(3);
  sway.translation_box = Box(whole, p.jerk_max, kY);
  sway.penalty_share = AllAtOnce(limits_, whole, kY);
  sway.rotation_box = Box(whole, p.jerk_max, kRoll);
  sway_ = std::make_unique<MpcChannel>(sway);

  MpcChannelSetup heave = Common(perception, p, period_s);
  heave.translation = heave.otolith = true;
  heave.force_offset_m_s2 = kStandardGravity_m_s2;
  heave.force_threshold = perception.Threshold(2);
  heave.translation_box = Box(whole, p.jerk_max, kZ);
  heave.penalty_share = AllAtOnce(limits_, whole, kZ);
  heave_ = std::make_unique<MpcChannel>(heave);

  MpcChannelSetup yaw = Common(perception, p, period_s);
  yaw.rotation = yaw.canal = true;
  yaw.rate_threshold = perception.Threshold(5);
  yaw.rotation_box = Box(whole, p.jerk_max, kYaw);
  yaw.penalty_share = AllAtOnce(limits_, whole, kYaw);
  yaw_ = std::make_unique<MpcChannel>(yaw);
}

HeadCue MpcCueing::Step(const VehicleSample& sample) {
  if (!sample.specific_force_m_s2.allFinite() || !sample.angular_velocity_rad_s.allFinite()) {
    throw std::invalid_argument("MPC cueing: a vehicle sample that is not finite");
  }
  const Vector3& f = sample.specific_force_m_s2;
  const Vector3& w = sample.angular_velocity_rad_s;
  MpcChannelVector input;
  input << std::max(std::fabs(f.x()) / thresholds_(0), std::fabs(w.y()) / thresholds_(4)),
      std::max(std::fabs(f.y()) / thresholds_(1), std::fabs(w.x()) / thresholds_(3)),
      std::fabs(f.z() - kStandardGravity_m_s2) / thresholds_(2), std::fabs(w.z()) / thresholds_(5);
  demand_ = input.cwiseMax(demand_ * demand_decay_);
  if (surge_->SolvesNext()) ShareTheLegs();
  surge_->Step(f.x(), w.y());
  sway_->Step(f.y(), w.x());
  heave_->Step(f.z(), 0.0);
  yaw_->Step(0.0, w.z());
  const Vector6 q = displacement();
  HeadCue cue;
  cue.rpy_rad = q.tail<3>();
  // The head where the platform's displacement puts it (CueToPlatformPose
  // takes it back exactly, about a level neutral pose).
  cue.position_m = q.head<3>() + RotationFromRpy(cue.rpy_rad) * head_ - head_;
  return cue;
}

void MpcCueing::ShareTheLegs() {
  const std::array<MpcChannel*, 4> all = {surge_.get(), sway_.get(), heave_.get(), yaw_.get()};
  std::array<MpcChannelVector, 3> held;
  for (int c = 0; c < kMpcChannels; ++c) {
    // Never more than it had: an inexact solve's plan a little outside its
    // box must not take the others' room; and a box shrinks slowly onto
    // its plan, or an inexact solve has no room left to stay inside it.
    const MpcChannel& channel = *all[static_cast<std::size_t>(c)];
    const Eigen::Vector3d had = channel.share();
    const Eigen::Vector3d plan = (channel.PlanShare() * kPlanSlack)
                                     .cwiseMax(had - Eigen::Vector3d::Constant(kShrinkPerSolve))
                                     .cwiseMin(had)
                                     .cwiseMax(kIdleReserve * channel.start_share());
    for (int kind = 0; kind < 3; ++kind) held[static_cast<std::size_t>(kind)](c) = plan(kind);
  }
  const MpcChannelVector position = room_.position.Allocate(held[0], demand_);
  const MpcChannelVector velocity = room_.velocity.Allocate(held[1], demand_);
  const MpcChannelVector acceleration = room_.acceleration.Allocate(held[2], demand_);
  for (int c = 0; c < kMpcChannels; ++c) {
    all[static_cast<std::size_t>(c)]->SetShare({position(c), velocity(c), acceleration(c)});
  }
}

void MpcCueing::Reset() {
  for (MpcChannel* channel : {surge_.get(), sway_.get(), heave_.get(), yaw_.get()}) channel->Reset();
  demand_.setZero();
}

Vector6 MpcCueing::displacement() const {
  Vector6 q;
  q << surge_->translation_m(), sway_->translation_m(), heave_->translation_m(), sway_->rotation_rad(),
      surge_->rotation_rad(), yaw_->rotation_rad();
  return q;
}

std::int64_t MpcCueing::unconverged_solves() const {
  std::int64_t n = 0;
  for (const MpcChannel* channel : channels()) n += channel->unconverged_solves();
  return n;
}

std::array<const MpcChannel*, 4> MpcCueing::channels() const {
  return {surge_.get(), sway_.get(), heave_.get(), yaw_.get()};
}

}  // namespace edsp
