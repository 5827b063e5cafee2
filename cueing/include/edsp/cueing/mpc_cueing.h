#pragma once
// Model-predictive cueing (docs/cueing.md, "Model-predictive cueing"): the
// platform's motion chosen every solve period to make the rider feel what
// the vehicle would, through the vestibular models, inside boxes of the
// platform's pose, velocity and acceleration that keep every leg inside
// its stroke, speed and acceleration limits (cueing/mpc_limits.h): the
// legs' room is shared among the channels before each solve, each keeping
// what its plan holds and the rest going where the vehicle's input is
// (its largest in thresholds per channel, held and let fade). After
// Dagdelen et al. 2009 and Khusro et al. 2020, linearised about the
// neutral pose in four channels that do not interact there:
//   surge  x with pitch  (fx, wy): tilt −g, the head +h ahead per rad
//   sway   y with roll   (fy, wx): tilt +g, the head −h per rad
//   heave  z             (fz − g)
//   yaw                  (wz)
// h is the head's height above the platform's origin (head_in_platform_m).
// The vehicle's input is held over the horizon; nothing is predicted
// beyond it.

#include <array>
#include <memory>

#include "edsp/cueing/classical_washout.h"
#include "edsp/cueing/mpc_channel.h"
#include "edsp/cueing/mpc_limits.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp {

struct MpcCueingParameters {
  // What the box may be at most, per axis (x y z m, roll pitch yaw rad);
  // DeriveMpcLimits scales each down until every leg's limits hold.
  MpcAxisLimits wanted = {(Vector6() << 0.15, 0.15, 0.10, 0.26, 0.26, 0.35).finished(),
                          (Vector6() << 0.4, 0.4, 0.3, 0.5, 0.5, 0.6).finished(),
                          (Vector6() << 4.0, 4.0, 4.0, 4.0, 4.0, 4.0).finished()};
  Vector6 jerk_max = (Vector6() << 40.0, 40.0, 40.0, 40.0, 40.0, 40.0).finished();
  double leg_margin = 0.05;    // of each leg's stroke room, speed and acceleration limit
  double demand_fade_s = 2.0;  // a channel's demand fades with this time constant once its input has gone
  MpcPenalties penalties;
  MpcHorizon horizon;
};

// Throws std::invalid_argument naming what is absurd.
void ValidateMpc(const MpcCueingParameters& parameters);

class MpcCueing {
 public:
  // The box is derived here (tens of milliseconds); throws
  // std::invalid_argument naming what is wrong.
  MpcCueing(const PlatformModel& model, const Pose& neutral, const Vector3& head_in_platform_m,
            const VestibularParameters& perception, const MpcCueingParameters& parameters, double period_s);

  // One setpoint period: the head's displacement from its neutral pose
  // (as ClassicalWashout's, for CueToPlatformPose). Throws
  // std::invalid_argument for a sample that is not finite.
  HeadCue Step(const VehicleSample& sample);
  // Back at the neutral pose with a rider at rest, as when made (the box kept).
  void Reset();

  // The box every channel may fill at once, and each channel's largest.
  const MpcAxisLimits& limits() const { return limits_; }
  const MpcLegRoom& room() const { return room_; }
  // The platform's displacement from the neutral pose (x y z roll pitch yaw).
  Vector6 displacement() const;
  // Over every channel since made.
  std::int64_t unconverged_solves() const;
  // The channels: surge, sway, heave, yaw.
  std::array<const MpcChannel*, 4> channels() const;

 private:
  void ShareTheLegs();

  Vector3 head_;
  MpcLegRoom room_;
  MpcAxisLimits limits_;
  Vector6 thresholds_;                                  // fx fy fz wx wy wz
  MpcChannelVector demand_ = MpcChannelVector::Zero();  // per channel, in thresholds
  double demand_decay_ = 1.0;                           // per Step
  std::unique_ptr<MpcChannel> surge_, sway_, heave_, yaw_;
};

}  // namespace edsp
