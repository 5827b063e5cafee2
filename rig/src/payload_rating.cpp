#include "edsp/rig/payload_rating.h"

#include <random>

#include "edsp/kinematics/platform_loads.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {

namespace {

Pose DrawPose(const PlatformModel& model, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> across(-0.5, 0.5), up(-0.3, 0.3), turn(-kTwoPi / 12.0, kTwoPi / 12.0);
  Vector6 q = model.home_pose().ToVector();
  q(0) += across(rng), q(1) += across(rng), q(2) += up(rng);
  for (int k = 3; k < 6; ++k) q(k) += turn(rng);
  return Pose::FromVector(q);
}

}  // namespace

PayloadRating RatePayload(const PlatformModel& model, const RigEffects::ServoLag& drives, const Vector3& com_M_m,
                          int poses) {
  PayloadRating rating;
  std::mt19937_64 rng(20211);
  const Vector3 gravity(0.0, 0.0, -9.81);
  for (int k = 0; k < poses; ++k) {
    const Pose X_BM = DrawPose(model, rng);
    if (!CheckWorkspace(model, X_BM).ok()) continue;
    const double force = LegForces(model, X_BM, Vector3::Zero(), 1.0, com_M_m, gravity).cwiseAbs().maxCoeff();
    if (force > rating.worst_force_per_kg) rating.worst_force_per_kg = force, rating.worst_pose = X_BM;
  }
  const DriveParameters& d = model.config().drive;
  // Motor torque per newton of leg force, through the screw and gearbox.
  const double torque_per_newton = d.lead_m / (kTwoPi * d.gear_ratio * drives.screw_efficiency);
  const double leg_force_n = kRatedTorqueShare * drives.torque_limit_N_m / torque_per_newton;
  if (rating.worst_force_per_kg > 0.0) rating.payload_kg = leg_force_n / rating.worst_force_per_kg;
  return rating;
}

}  // namespace edsp
