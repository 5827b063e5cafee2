#pragma once
// A second virtual rig, written apart from rig/ and diagnosis/ (its own
// kinematics, motions, statics and formulation of every effect): it writes
// the measurement CSV of interfaces.md §3 for a platform with effects the
// diagnosis must find, and effects outside its vocabulary it must call
// `unknown`. edsp-gap is scored on it beside edsp's own rig, so a bug shared
// by edsp's rig and its diagnosis cannot hide (docs/diagnosis.md).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "edsp/blindrig/blind_kinematics.h"
#include "edsp/blindrig/blind_motions.h"

namespace edsp::blind {

// What the platform really does beyond the controller's nominal model. Zero
// (or the default) is off for each.
struct BlindEffects {
  bool pr_override = false;                      // passive_rotation: the screws' true s differs
  int true_pr_sign = 1;                          //   ±1, or 0 for screws without PR
  Vec6 leg_offset_m = Vec6::Zero();              // leg_offset: length at encoder zero, beyond nominal
  Mat36 base_joint_error_m = Mat36::Zero();      // joint_position, in {B}
  Mat36 platform_joint_error_m = Mat36::Zero();  //   and in {M}
  Vec6 lead_error = Vec6::Zero();                // lead_error: travel × (1 + ε)
  Vec6 periodic_amplitude_m = Vec6::Zero(), periodic_phase_rad = Vec6::Zero();  // once per screw turn
  Vec6 backlash_m = Vec6::Zero();     // backlash: play between motor and screw travel
  double servo_bandwidth_hz = 0.0;    // servo_lag: critically damped motor loop (0: ideal)
  Vec6 stiffness_N_m = Vec6::Zero();  // compliance: axial (0: rigid)
  double mass_kg = 0.0;               //   the moving platform, centre of mass in {M}
  Vec3 com_M = Vec3::Zero();
  double alpha_per_K = 0.0;      // thermal_drift: the screw grows α·ΔT·(half screw + travel)
  double heating_K_per_m = 0.0;  //   heating by leg travel
  double heating_K_per_s = 0.0;  //   heating by time under power (a motor warming its screw)
  double thermal_tau_s = 900.0;  //   cooling time constant
  double screw_length_m = 0.6;
  double resonance_hz = 0.0;        // structural_resonance: a lightly damped sway of the structure
  double resonance_damping = 0.02;  //   carrying A, excited by A's acceleration (displacement per
  double resonance_gain = 0.0;      //   acceleration: gain / ω² at low frequency)
  // Outside edsp-gap's vocabulary:
  double floor_hz = 0.0;  // the tracker's stand vibrating on the floor
  double floor_amplitude_m = 0.0;
  Vec3 floor_direction = Vec3::UnitX();
  double base_tilt_rad_per_N_m = 0.0;       // the base mount's rotational give under the platform's moment
  Vec3 stand_drift_m_per_s = Vec3::Zero();  // the tracker's stand settling: its readings creep
  double stand_settle_s = 300.0;            //   at this rate, slowing with this time constant
  double clock_drift = 0.0;                 // the tracker's clock gains this fraction on the controller's:
                                            //   its readings fall later and later over the session
  double target_reseat_m = 0.0;             // the tracker's target re-seated in its nest before each run:
                                 //   A sits this far (RMS) from its nominal centre, drawn anew each run, in {M}
  // A change within the session, not an effect: from `change_time_s` of the
  // session on (< 0: never), leg `change_leg` (0-based; -1: none) is
  // `change_m` longer (a coupling slipping, a joint re-seated) and the
  // tracker's pose of {B} has moved by `change_tracker` (x y z, roll pitch
  // yaw: its stand knocked).
  double change_time_s = -1.0;
  int change_leg = -1;
  double change_m = 0.0;
  Vec6 change_tracker = Vec6::Zero();
};

struct TrackerOptions {
  double rate_hz = 100.0;
  double noise_m = 10e-6;                                             // 1-σ per axis
  bool encoders = true;                                               // write leg_enc_* columns
  Vec6 frame = (Vec6() << 1.8, -0.7, 0.3, 0.0, 0.0, 0.5).finished();  // tracker pose of {B}: x y z r p y
  std::uint64_t seed = 1;                                             // noise
  // How late the tracker's readings are (s; its clock ahead of the
  // controller's by that much): a row stamped t holds the reading of
  // instant t − offset (− clock_drift·t with BlindEffects' drift). A
  // nuisance, not an effect: edsp-gap estimates it from encoder columns
  // (docs/diagnosis.md).
  double time_offset_s = 0.0;
};

// A calibration the controller applies beside its nominal model (edsp's,
// scored on this rig): the correction it takes off the nominal command at
// session time `time_s`, for the commanded pose, its rates (the pose
// vector's derivatives) and the nominal command. Called once per control
// step, in order of time.
using ControllerCalibration = std::function<Vec6(double time_s, const Vec6& pose, const Vec6& velocity,
                                                 const Vec6& acceleration, const Vec6& command_m)>;

struct BlindRigSetup {
  BlindGeometry geometry;  // nominal: what the controller and the diagnosis believe
  double lead_m = 0.010;
  int pr_sign = 1;  // the controller compensates signed PR with this s
  std::vector<std::string> motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2", "M3", "M4"};
  // Motions of `motions` another controller plans (edsp's), by name; the
  // rest are this rig's own.
  std::vector<SampledMotion> sampled_motions;
  MotionLimits limits;
  double control_rate_hz = 1000.0;
  // Empty: the nominal controller. Set: its correction is taken off every
  // command, and the CSV records it (leg_corr_* columns).
  ControllerCalibration calibration;
};

// The motion `name` as the rig runs it: from the setup's sampled motions if
// there, else its own. Throws std::invalid_argument for a name it lacks.
BlindMotion MotionNamed(const BlindRigSetup& setup, const std::string& name);

// The measurement CSV of every motion, one after another in one session.
// Throws std::runtime_error if a pose cannot be solved (an absurd effect).
std::string GenerateMeasurementCsv(const BlindRigSetup& setup, const BlindEffects& effects,
                                   const TrackerOptions& tracker);

// A drawn scenario: the effects, the truth in the diagnosis's vocabulary
// (empty: effect-free), its kind, and the tracker it is measured with.
struct BlindScenario {
  std::string kind;                // none | single | pair | out_of_vocabulary
  std::vector<std::string> truth;  // vocabulary names; out_of_vocabulary: its own name
  BlindEffects effects;
  TrackerOptions tracker;
  std::string description;
};

// Scenario `index` of a seed: index % 5 == 0 effect-free, 1–2 one effect,
// 3 two, 4 out of the vocabulary; tracker rate 10–1000 Hz, σ 2–20 µm, with
// or without encoder columns, all drawn. `encoders`, if set, overrides the
// last draw only: every other part of the scenario is the one drawn.
BlindScenario DrawBlindScenario(std::uint64_t seed, int index, std::optional<bool> encoders = std::nullopt);

// Rig `index` of a seed with every static effect class at once, as a real
// rig has them: leg offsets ±120 µm, joint centres σ 100 µm, lead errors
// ±250 ppm with a once-per-turn error of 2–8 µm, backlash 15–40 µm, legs of
// 15–30 N/µm (±10% leg to leg) under 500 kg up to `payload_max_kg`, its
// centre of mass up to 0.3 m above {M}; the tracker 5 µm at 100 Hz with
// encoders, its stand anywhere on the floor. Kind "whole_rig".
BlindScenario DrawBlindWholeRig(std::uint64_t seed, int index, double payload_max_kg);

// Rig `index` of a seed with every class at once: DrawBlindWholeRig's, a
// soft servo loop (10–30 Hz), screws warming by travel or by time under
// power, half the rigs with screws whose passive rotation is not the
// controller's, and payloads from light to heavy (log-uniform from 100 kg
// up to `payload_max_kg`). Kind "whole_rig".
BlindScenario DrawBlindEveryClassRig(std::uint64_t seed, int index, double payload_max_kg);

// Names of the out-of-vocabulary kinds it draws.
std::vector<std::string> OutOfVocabularyKinds();

}  // namespace edsp::blind
