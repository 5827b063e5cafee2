#include "edsp/gap/rig_scenarios.h"
#include "draws.h"
#include "edsp/rig/payload_rating.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <fmt/format.h>

namespace edsp::gap {

namespace {

double Signed(Rng& rng, double lo, double hi) { return Uniform(rng, lo, hi) * (Uniform(rng, 0, 1) < 0.5 ? -1 : 1); }

// A wrong PR compensation in the controller, or screws whose PR is not the model's.
void DrawPassiveRotation(Rng& rng, Scenario* s) {
  RigEffects& fx = s->effects;
  const int variant = static_cast<int>(Uniform(rng, 0, 4));
  if (variant == 0) {
    s->compensation = PrMode::kUnsigned;  // the paper's Eq. (9)
    s->description += "PR compensated unsigned; ";
  } else if (variant == 1) {
    s->compensation = PrMode::kNone;
    s->description += "PR not compensated; ";
  } else if (variant == 2) {
    fx.passive_rotation.enabled = true;
    fx.passive_rotation.pr_sign = -1;  // the other thread hand
    s->description += "screws of the other hand (PR sign −1); ";
  } else {
    fx.passive_rotation.enabled = true;
    const double scale = Uniform(rng, 0, 1) < 0.5 ? Uniform(rng, 0.6, 0.85) : Uniform(rng, 1.15, 1.4);
    fx.passive_rotation.pr_lead_m = 0.010 * scale;
    s->description += fmt::format("PR through a {:.2f}× lead; ", scale);
  }
}

void DrawLegOffset(Rng& rng, Scenario* s) {
  s->effects.leg_offset.enabled = true;
  for (double& v : s->effects.leg_offset.offset_m) v = Signed(rng, 30e-6, 150e-6);
  s->description += "leg offsets 30–150 µm; ";
}

void DrawJointPosition(Rng& rng, Scenario* s) {
  RigEffects::JointPosition& joints = s->effects.joint_position;
  joints.enabled = true;
  std::normal_distribution<double> n(0.0, 100e-6);
  for (int i = 0; i < 6; ++i) {
    for (int a = 0; a < 3; ++a) {
      joints.base_m(a, i) = n(rng);
      joints.platform_m(a, i) = n(rng);
    }
  }
  s->description += "joint centres σ 100 µm; ";
}

void DrawLeadError(Rng& rng, Scenario* s) {
  s->effects.lead_error.enabled = true;
  for (double& v : s->effects.lead_error.epsilon) v = Signed(rng, 80e-6, 300e-6);
  s->description += "lead errors 80–300 ppm; ";
}

void DrawPeriodicLeadError(Rng& rng, Scenario* s) {
  RigEffects::PeriodicLeadError& periodic = s->effects.periodic_lead_error;
  periodic.enabled = true;
  for (std::size_t i = 0; i < 6; ++i) {
    periodic.amplitude_m[i] = Uniform(rng, 5e-6, 12e-6);
    periodic.phase_rad[i] = Uniform(rng, 0, 6.283185307179586);
  }
  s->description += "periodic lead error 5–12 µm; ";
}

void DrawBacklash(Rng& rng, Scenario* s) {
  s->effects.backlash.enabled = true;
  for (double& v : s->effects.backlash.backlash_m) v = Uniform(rng, 15e-6, 60e-6);
  s->description += "backlash 15–60 µm; ";
}

void DrawServoLag(Rng& rng, Scenario* s) {
  s->effects.servo_lag.bandwidth_hz = Uniform(rng, 8.0, 20.0);  // a soft loop without integral action
  s->effects.servo_lag.integral_time_s = 0.0;
  s->description += fmt::format("servo loop {:.1f} Hz; ", s->effects.servo_lag.bandwidth_hz);
}

void DrawCompliance(Rng& rng, Scenario* s) {
  RigEffects::Compliance& compliance = s->effects.compliance;
  compliance.enabled = true;
  const double k0 = Uniform(rng, 1e7, 3e7);  // legs of one design, ±15% from assembly
  for (double& v : compliance.stiffness_N_m) v = k0 * Uniform(rng, 0.85, 1.15);
  compliance.mass_kg = Uniform(rng, 400, 1200);
  compliance.com_m = Vector3(0, 0, Uniform(rng, 0.0, 0.3));
  s->description += fmt::format("compliance, {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/µm legs ±15%; ",
                                compliance.mass_kg, compliance.com_m.z(), compliance.stiffness_N_m[0] * 1e-6);
}

void DrawThermalDrift(Rng& rng, Scenario* s) {
  s->effects.thermal_drift.enabled = true;
  s->effects.thermal_drift.heating_K_per_m = Uniform(rng, 3.0, 8.0);
  s->effects.thermal_drift.time_constant_s = Uniform(rng, 600, 1800);
  s->description += fmt::format("thermal drift {:.1f} K/m; ", s->effects.thermal_drift.heating_K_per_m);
}

// The mount of the tracker's reflector (a mast on the platform) sways at a
// few hertz, more sideways than up.
void DrawStructuralResonance(Rng& rng, Scenario* s) {
  RigEffects::StructuralResonance& mode = s->effects.structural_resonance;
  mode.enabled = true;
  mode.frequency_hz = Uniform(rng, 3.0, 10.0);
  mode.damping = Uniform(rng, 0.01, 0.05);
  mode.gain = Vector3(Uniform(rng, 0.1, 0.5), Uniform(rng, 0.1, 0.5), Uniform(rng, 0.0, 0.2));
  s->description += fmt::format("structure sways at {:.1f} Hz (ζ {:.3f}, gains {:.2f} {:.2f} {:.2f}); ",
                                mode.frequency_hz, mode.damping, mode.gain.x(), mode.gain.y(), mode.gain.z());
}

// How each effect of the vocabulary is put on the rig, in the order of the enum.
struct EffectDraw {
  Effect effect;
  void (*draw)(Rng&, Scenario*);
};
constexpr std::array<EffectDraw, kEffectCount> kDraws = {{
    {Effect::kPassiveRotation, DrawPassiveRotation},
    {Effect::kLegOffset, DrawLegOffset},
    {Effect::kJointPosition, DrawJointPosition},
    {Effect::kLeadError, DrawLeadError},
    {Effect::kPeriodicLeadError, DrawPeriodicLeadError},
    {Effect::kBacklash, DrawBacklash},
    {Effect::kServoLag, DrawServoLag},
    {Effect::kCompliance, DrawCompliance},
    {Effect::kThermalDrift, DrawThermalDrift},
    {Effect::kStructuralResonance, DrawStructuralResonance},
}};

constexpr bool InEnumOrder() {
  for (std::size_t k = 0; k < kDraws.size(); ++k) {
    if (static_cast<std::size_t>(kDraws[k].effect) != k) return false;
  }
  return true;
}
static_assert(InEnumOrder(), "kDraws must list the effects in the order of the enum");

}  // namespace

Scenario DrawScenario(std::uint64_t seed, int index) {
  Rng rng(seed * 1000003ull + static_cast<std::uint64_t>(index));
  Scenario s;
  // Every rig has a drive loop; a well-tuned one (integral action) leaves
  // no lag worth the name: the effect-free baseline.
  s.effects.servo_lag.integral_time_s = 0.05;
  s.effects.servo_lag.torque_limit_N_m = 15.0;  // motors sized for the heaviest payload drawn
  const int kind = index % 5;
  const int count = kind == 0 ? 0 : (kind <= 2 ? 1 : 2);
  std::vector<Effect> pool = AllEffects();
  std::shuffle(pool.begin(), pool.end(), rng);
  for (int k = 0; k < count; ++k) {
    const Effect e = pool[static_cast<std::size_t>(k)];
    s.truth.push_back(e);
    kDraws[static_cast<std::size_t>(e)].draw(rng, &s);
  }
  if (s.truth.empty()) s.description = "no effect (the rig's stiff default drive loop only)";
  return s;
}

Scenario DrawWholeRig(std::uint64_t seed, int index, double rated_payload_kg) {
  Rng rng(seed * 2000003ull + static_cast<std::uint64_t>(index));
  Scenario s;
  RigEffects& fx = s.effects;
  fx.leg_offset.enabled = fx.joint_position.enabled = fx.lead_error.enabled = true;
  fx.periodic_lead_error.enabled = fx.backlash.enabled = fx.compliance.enabled = true;
  std::normal_distribution<double> joint(0.0, 100e-6);
  const double k0 = Uniform(rng, 15e6, 30e6);  // legs of one design, ±10% from assembly
  for (std::size_t i = 0; i < 6; ++i) {
    fx.leg_offset.offset_m[i] = Uniform(rng, -120e-6, 120e-6);
    fx.lead_error.epsilon[i] = Uniform(rng, -250e-6, 250e-6);
    fx.periodic_lead_error.amplitude_m[i] = Uniform(rng, 2e-6, 8e-6);
    fx.periodic_lead_error.phase_rad[i] = Uniform(rng, 0, 6.283185307179586);
    fx.backlash.backlash_m[i] = Uniform(rng, 15e-6, 40e-6);
    fx.compliance.stiffness_N_m[i] = k0 * Uniform(rng, 0.9, 1.1);
    for (int a = 0; a < 3; ++a) {
      fx.joint_position.base_m(a, static_cast<int>(i)) = joint(rng);
      fx.joint_position.platform_m(a, static_cast<int>(i)) = joint(rng);
    }
  }
  fx.compliance.mass_kg = Uniform(rng, 500.0, std::max(500.0, rated_payload_kg));
  fx.compliance.com_m = Vector3(0, 0, Uniform(rng, 0.0, kWholeRigComHeightMaxM));
  fx.servo_lag.bandwidth_hz = Uniform(rng, 30.0, 80.0);
  fx.servo_lag.integral_time_s = 5.0 / (6.283185307179586 * fx.servo_lag.bandwidth_hz);
  s.truth = {Effect::kLegOffset,         Effect::kJointPosition, Effect::kLeadError,
             Effect::kPeriodicLeadError, Effect::kBacklash,      Effect::kCompliance};
  s.description = fmt::format("whole rig: {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/µm legs, {:.0f} Hz drives",
                              fx.compliance.mass_kg, fx.compliance.com_m.z(), k0 * 1e-6, fx.servo_lag.bandwidth_hz);
  return s;
}

double WholeRigRatedPayload(const PlatformModel& model) {
  return RatePayload(model, RigEffects{}.servo_lag, Vector3(0, 0, kWholeRigComHeightMaxM)).payload_kg;
}

Scenario DrawEveryClassRig(std::uint64_t seed, int index, double rated_payload_kg) {
  Scenario s = DrawWholeRig(seed, index, rated_payload_kg);
  Rng rng(seed * 3000017ull + static_cast<std::uint64_t>(index));
  const double heaviest = std::max(kEveryClassPayloadMinKg, rated_payload_kg);
  s.effects.compliance.mass_kg =
      kEveryClassPayloadMinKg * std::exp(Uniform(rng, 0.0, std::log(heaviest / kEveryClassPayloadMinKg)));
  s.description =
      fmt::format("every class: {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/µm legs; ", s.effects.compliance.mass_kg,
                  s.effects.compliance.com_m.z(), s.effects.compliance.stiffness_N_m[0] * 1e-6);
  DrawServoLag(rng, &s);
  // A drive loop without integral action would let the payload sag the
  // legs by g/ω² (a millimetre at 12 Hz): no rig runs so. Soft but
  // integrating, it lags in motion and holds the weight at rest.
  s.effects.servo_lag.integral_time_s = 5.0 / (6.283185307179586 * s.effects.servo_lag.bandwidth_hz);
  s.description += "with integral action; ";
  DrawThermalDrift(rng, &s);
  s.truth.push_back(Effect::kServoLag);
  s.truth.push_back(Effect::kThermalDrift);
  if (Uniform(rng, 0, 1) < 0.5) {
    DrawPassiveRotation(rng, &s);
    s.truth.push_back(Effect::kPassiveRotation);
  }
  return s;
}

Pose DrawTrackerStand(std::mt19937_64& rng) {
  return Pose::FromVector((Vector6() << Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -0.5, 0.5),
                           Uniform(rng, -0.03, 0.03), Uniform(rng, -0.03, 0.03), Uniform(rng, -3.14, 3.14))
                              .finished());
}

}  // namespace edsp::gap
