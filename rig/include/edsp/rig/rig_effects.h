#pragma once
// The physical effects a nominal model leaves out (interfaces.md §4), as
// parameters of the virtual rig's physics. Each is off unless its table is
// present in the platform config's [rig.effects] section (and not
// `enabled = false`), except servo_lag: the drive loop is on unless
// switched off. With all off the rig is the nominal model (screws with the
// nominal signed PR, an ideal drive, rigid legs, screws at ambient), and
// point A lands where the model says to numerical precision. Units SI; per-leg values are a number (every leg) or 6
// numbers.
//
//   [rig.effects.leg_offset]           offset_m = [...]        home-length (zero) offsets
//   [rig.effects.joint_position]       base_m = [[dx,dy,dz] ×6], platform_m = [[...] ×6]
//   [rig.effects.passive_rotation]     pr_sign = 1|-1|0 (0: no PR), pr_lead_m = 0.010
//   [rig.effects.lead_error]           epsilon = [...]         lead·(1+ε) per turn
//   [rig.effects.periodic_lead_error]  amplitude_m = [...], phase_rad = [...]   once per screw turn
//   [rig.effects.backlash]             backlash_m = [...]      lost motion, in leg travel
//   [rig.effects.servo_lag]            bandwidth_hz, inertia_kg_m2, viscous_N_m_s,
//                                      torque_limit_N_m, loop_rate_hz, following_error_window_m
//                                                                   the drive loop's dynamics
//   [rig.effects.compliance]           stiffness_N_m = [...], mass_kg, com_m = [x, y, z] in {M}
//   [rig.effects.thermal_drift]        alpha_per_K, heating_K_per_m, time_constant_s, screw_length_m
//   [rig.effects.structural_resonance] frequency_hz, damping, gain = [gx, gy, gz]   A's mount sways
//
// docs/rig.md gives each effect's physics, realistic magnitudes for a
// platform of the paper's size, and the signature it leaves at point A.

#include <array>
#include <string>
#include <vector>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/leg_effects.h"
#include "edsp/kinematics/types.h"

namespace edsp {

using LegValues = std::array<double, 6>;

struct RigEffects {
  struct LegOffset {
    bool enabled = false;
    LegValues offset_m{};
  } leg_offset;
  struct JointPosition {
    bool enabled = false;
    Matrix36 base_m = Matrix36::Zero();      // added to the base joint centres, {B}
    Matrix36 platform_m = Matrix36::Zero();  // added to the platform joint centres, {M}
  } joint_position;
  struct PassiveRotation {
    bool enabled = false;
    int pr_sign = 1;         // the screws' true s: 1, -1, or 0 for none at all
    double pr_lead_m = 0.0;  // the lead PR acts through; 0: the nominal lead
  } passive_rotation;
  struct LeadError {
    bool enabled = false;
    LegValues epsilon{};  // relative error of the lead
  } lead_error;
  struct PeriodicLeadError {
    bool enabled = false;
    LegValues amplitude_m{};  // leg travel error, once per screw turn
    LegValues phase_rad{};
  } periodic_lead_error;
  struct Backlash {
    bool enabled = false;
    LegValues backlash_m{};  // total lost motion, in leg travel
  } backlash;
  struct ServoLag {                  // on unless switched off: the drive loop every real rig has;
    bool enabled = true;             // off: an ideal drive, the motor exactly on its target
    double inertia_kg_m2 = 2e-4;     // motor + reflected screw, at the motor
    double viscous_N_m_s = 1e-4;     // per rad/s
    double torque_limit_N_m = 15.0;  // current limit × torque constant (holds 1.2 t over the
                                     // preset's workspace with a third to spare: RatePayload)
    double bandwidth_hz = 50.0;      // position loop; gains follow from it
    double loop_rate_hz = 4000.0;    // drive loop and integration rate
    double coulomb_N_m = 0.0;        // dry friction in screw and bearings, at the motor
    double integral_time_s = 0.0;    // the loop's integral action (0: none, a P-D loop)
    double screw_efficiency = 0.9;   // leg force → motor torque through the screw
    double load_mass_kg = 0.0;       // platform + payload the motors carry (compliance's
                                     // mass_kg and com_m when that effect is on)
    // Following error (target − motor, in leg travel) past which a drive
    // faults and its brake holds the motor where it is, as a CiA 402
    // drive's following-error window does: an overloaded motor stops the
    // platform instead of letting it fall through its legs. 0: no window
    // (the rig's tests step its targets by centimetres on purpose).
    double following_error_window_m = 0.0;
  } servo_lag;
  struct Compliance {  // quasi-static: legs deflect under the rigid-body leg forces
    bool enabled = false;
    LegValues stiffness_N_m{};        // axial, leg + both joints
    double mass_kg = 0.0;             // the moving platform
    Vector3 com_m = Vector3::Zero();  // its centre of mass in {M}
    double payload_kg = 0.0;          // what it carries (a second payload separates compliance)
    Vector3 payload_com_m = Vector3::Zero();
    double total_mass_kg() const { return mass_kg + payload_kg; }
    Vector3 total_com_m() const {
      return total_mass_kg() > 0.0 ? (mass_kg * com_m + payload_kg * payload_com_m) / total_mass_kg() : com_m;
    }
    Vector3 gravity_m_s2 = Vector3(0.0, 0.0, -9.81);  // in {B}
  } compliance;
  struct ThermalDrift {  // screws warm with the work they do and grow
    bool enabled = false;
    double alpha_per_K = 11.7e-6;    // steel
    double heating_K_per_m = 0.0;    // temperature rise per metre of leg travel
    double time_constant_s = 600.0;  // cooling towards ambient
    double screw_length_m = 0.6;     // the length of screw that warms and grows
  } thermal_drift;
  struct StructuralResonance {  // the structure carrying A sways under the platform's acceleration
    bool enabled = false;       // (structural_mode.h): per axis of {B}, gain × the mode's response
    double frequency_hz = 5.0;
    double damping = 0.03;
    Vector3 gain = Vector3::Zero();
  } structural_resonance;

  bool any() const;
};

// Reads [rig.effects] from a config file's text (other sections are the
// nominal model's). Throws ConfigError naming the file, line and key for an
// unknown effect or key, a missing or absurd value.
RigEffects ParseRigEffects(const std::string& toml_text, const std::string& origin);
RigEffects LoadRigEffects(const std::string& path);

// The enabled effects, in a fixed order (their names, interfaces.md §4:
// calibration::EffectName).
std::vector<calibration::Effect> EnabledEffects(const RigEffects& effects);
// `effects` with every effect but `effect` switched off (and that one as
// it was).
RigEffects OnlyEffect(const RigEffects& effects, calibration::Effect effect);

// The rig as built: the nominal geometry with the joint positions moved.
PlatformConfig TrueConfig(const PlatformConfig& nominal, const RigEffects& effects);

}  // namespace edsp
