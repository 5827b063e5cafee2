#pragma once
// The virtual EDSP that stands in for hardware. Per leg a drive (ideal, or
// with the servo_lag effect a motor with inertia, viscous friction and a
// torque limit under a position/velocity loop with velocity feed-forward), a
// drive train (LegTransmission: backlash, lead errors, leg offsets) and a
// screw that adds its TRUE signed passive rotation: the platform sits at the
// pose whose leg lengths match, found by forward kinematics on the rig's own
// geometry (joint_position). With no effect on, it is the nominal model. A
// laser-tracker emulator measures point A in its own frame.

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "edsp/drive_io/drive_backend.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/kinematics/structural_mode.h"
#include "edsp/rig/leg_transmission.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

struct TrackerParameters {
  Pose X_TB;                   // {B} in the tracker frame (identity: the same)
  double noise_sigma_m = 0.0;  // per axis
  double rate_hz = 1000.0;
  std::uint64_t seed = 1;
};

// The drives' side of a process image that stops updating (a frozen or
// killed bridge, a lost fieldbus): like a real drive's interpolator, the
// target follows the last velocity feed-forward for a few cycles only, then
// stays where it is (the drive holds position; it never runs on for ever);
// past the watchdog the drives report themselves holding.
struct DriveWatchdog {
  double interpolation_horizon_s = 0.004;  // 4 cycles of the 1 kHz image
  double timeout_s = 0.02;                 // then status kHolding, until a command
};

struct RigParameters {
  PlatformConfig nominal;  // what the rig was designed to be
  RigEffects effects;      // how it really is (none: exactly nominal)
  TrackerParameters tracker;
  DriveWatchdog watchdog;
};

// RigParameters for a rig built exactly to `nominal`, tracker frame = {B}.
RigParameters IdealRig(const PlatformConfig& nominal);

class VirtualRig {
 public:
  explicit VirtualRig(RigParameters parameters);

  void SetTarget(const DriveSetpoint& setpoint, bool enabled);
  // The same command again (a master that re-sends its last frame, a drive
  // simulator between the fieldbus and the rig): the drives' watchdog sees a
  // live master, but the interpolator does not start over: a stale command
  // re-sent is not a new one, and the target stays where the horizon left it.
  void KeepAlive() { since_command_s_ = 0.0; }
  // The motors where they are (absolute encoders): a rig emulator restarted
  // after a crash continues from its predecessor's last drive feedback, as
  // real hardware does not move when its controller restarts. Drives off,
  // the platform where those angles put it. False if no pose fits them.
  bool RestoreDrives(const std::array<double, 6>& motor_angle_rad);
  // Advances time by dt_s: servo loops at their rate, then the platform pose.
  // Returns false if the platform pose could not be found (a broken rig).
  bool Advance(double dt_s);

  DriveFeedback Feedback() const;
  // Enabled drives without a command for longer than the watchdog timeout.
  bool watchdog_tripped() const;
  // A drive whose following error passed its window (servo_lag's
  // following_error_window_m): it reports kFault and its brake holds the
  // motor until the drives are disabled (the fault reset).
  bool drive_faulted(int leg) const { return faulted_[static_cast<std::size_t>(leg)]; }
  bool any_drive_faulted() const;
  double since_command_s() const { return since_command_s_; }
  rig_truth_t Truth(std::int64_t utime);  // numbers each message (seq)
  // True (and *point filled) when a tracker sample is due at this step.
  bool TrackerSample(std::int64_t utime, tracker_point_t* point);

  const Pose& true_pose() const { return pose_; }
  const PlatformModel& true_model() const { return model_; }
  const Vector6& drive_train_lengths() const { return lengths_; }
  const Vector6& leg_forces() const { return leg_forces_; }  // compliance: N, + compression
  // Point A where it is: on the platform, plus the structure's sway.
  Vector3 ObservedPoint() const;

 private:
  void StepServo(int leg, double dt);
  void StepIdeal(int leg, double dt);
  bool UpdateLoads(double dt_s);         // leg forces of the platform's rigid-body motion
  double ScrewRatio() const;             // motor torque per newton of leg force
  double MovedInertia() const;           // motor, screw and its share of the payload, at the motor
  void Deflect(Vector6* lengths) const;  // compliance: legs shortened under them
  void Sway(double dt_s);                // structural_resonance: A's mount under its acceleration

  RigParameters parameters_;
  PlatformModel model_;  // the true geometry; lead and sign of the true PR
  FkOptions fk_options_;
  std::vector<LegTransmission> transmissions_;
  Vector6 lengths_ = Vector6::Zero();  // drive-train lengths (before deflection)
  Pose rigid_pose_, rigid_previous_;   // the undeflected platform, for its acceleration
  int rigid_history_ = 0;
  Vector6 leg_forces_ = Vector6::Zero();         // with the platform's acceleration (compliance)
  Vector6 static_leg_forces_ = Vector6::Zero();  // its weight alone (the motors' load torque)
  double load_mass_per_leg_kg_ = 0.0;            // reflected to each motor as inertia
  double kp_, kd_, ki_ = 0.0;
  std::array<double, 6> integral_{};
  bool loaded_ = false;  // leg forces needed (compliance, or a servo load)
  std::array<double, 6> angle_{}, velocity_{};
  std::array<bool, 6> faulted_{};
  DriveSetpoint target_;
  bool enabled_ = false;
  double since_command_s_ = 0.0;  // since the last SetTarget or KeepAlive (the watchdog)
  double since_target_s_ = 0.0;   // since the last SetTarget (the interpolation horizon)
  Pose pose_;
  std::optional<StructuralMode> mode_;      // structural_resonance
  std::array<Vector3, 2> point_history_{};  // A on the platform a step and two steps ago
  double last_dt_s_ = 0.0;
  int point_steps_ = 0;
  Vector3 sway_ = Vector3::Zero();
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
  // False while a drive is in fault (the bridge then holds every leg).
  bool Read(std::int64_t now_utime, DriveFeedback* feedback) override;
  bool Write(std::int64_t now_utime, const DriveSetpoint& setpoint) override;
  bool Reset(std::string* error) override;
  BackendState state() const override { return state_; }

 private:
  VirtualRig* rig_;
  BackendState state_ = BackendState::kUnconfigured;
};

}  // namespace edsp
