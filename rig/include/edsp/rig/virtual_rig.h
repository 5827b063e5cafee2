#pragma once
// The virtual EDSP that stands in for hardware. Per leg a motor (inertia,
// viscous friction, torque limit) driven by a position/velocity loop with
// velocity feed-forward at `loop_rate_hz`. Each screw adds its TRUE signed
// passive rotation: the platform sits at the pose whose true leg lengths
// (encoder-implied length + true PR error) match, found by forward
// kinematics on the rig's own, possibly non-nominal, geometry. A laser-tracker
// emulator measures point A in its own frame.

#include <cstdint>
#include <random>

#include "edsp/actuator_bridge/drive_backend.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

struct ServoParameters {
  double inertia_kg_m2 = 2e-4;      // motor + reflected screw, at the motor
  double viscous_N_m_s = 1e-4;      // per rad/s
  double torque_limit_N_m = 5.0;    // current limit × torque constant
  double bandwidth_hz = 50.0;       // position loop; gains follow from it
  double loop_rate_hz = 4000.0;     // drive loop and integration rate
};

struct TrackerParameters {
  Pose X_TB;                        // {B} in the tracker frame (identity: the same)
  double noise_sigma_m = 0.0;       // per axis
  double rate_hz = 1000.0;
  std::uint64_t seed = 1;
};

struct RigParameters {
  PlatformConfig true_config;       // the rig as built (may differ from nominal)
  ServoParameters servo;
  TrackerParameters tracker;
};

// RigParameters for a rig built exactly to `nominal`, tracker frame = {B}.
RigParameters IdealRig(const PlatformConfig& nominal);

class VirtualRig {
 public:
  explicit VirtualRig(RigParameters parameters);

  void SetTarget(const DriveSetpoint& setpoint, bool enabled);
  // Advances time by dt_s: servo loops at their rate, then the platform pose.
  // Returns false if the platform pose could not be found (a broken rig).
  bool Advance(double dt_s);

  DriveFeedback Feedback() const;
  rig_truth_t Truth(std::int64_t utime);  // numbers each message (seq)
  // True (and *point filled) when a tracker sample is due at this step.
  bool TrackerSample(std::int64_t utime, tracker_point_t* point);

  const Pose& true_pose() const { return pose_; }
  const PlatformModel& true_model() const { return model_; }

 private:
  void StepServo(int leg, double dt);

  RigParameters parameters_;
  PlatformModel model_;  // the true geometry, lead and PR sign
  double kp_, kd_;
  std::array<double, 6> angle_{}, velocity_{};
  DriveSetpoint target_;
  bool enabled_ = false;
  Pose pose_;
  double time_s_ = 0.0;
  double next_tracker_s_ = 0.0;
  std::mt19937_64 rng_;
  std::int64_t truth_seq_ = 0, tracker_seq_ = 0;
};

// The virtual rig as a DriveBackend, stepped in-process by the simulation
// (the edsp-rig process serves the same rig through a shared-memory process
// image instead).
class InProcessRigBackend final : public DriveBackend {
 public:
  explicit InProcessRigBackend(VirtualRig* rig) : rig_(rig) {}
  bool Configure(const PlatformConfig&, std::string*) override;
  bool Activate(std::string* error) override;
  void Deactivate() override;
  bool Read(std::int64_t now_utime, DriveFeedback* feedback) override;
  bool Write(std::int64_t now_utime, const DriveSetpoint& setpoint) override;
  BackendState state() const override { return state_; }

 private:
  VirtualRig* rig_;
  BackendState state_ = BackendState::kUnconfigured;
};

}  // namespace edsp
