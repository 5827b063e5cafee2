// Scenario draws of the second rig: magnitudes of a real platform of the
// paper's size (docs/diagnosis.md, "The independent rig").
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "edsp/blindrig/blind_rig.h"

namespace edsp::blind {

namespace {

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  double LogUniform(double lo, double hi) { return std::exp(Uniform(std::log(lo), std::log(hi))); }
  double Signed(double lo, double hi) { return (Uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0) * Uniform(lo, hi); }
  int Index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  Vec6 PerLeg(double lo, double hi) {
    Vec6 v;
    for (int i = 0; i < 6; ++i) v(i) = Signed(lo, hi);
    return v;
  }
  Vec6 PerLegPositive(double lo, double hi) {
    Vec6 v;
    for (int i = 0; i < 6; ++i) v(i) = Uniform(lo, hi);
    return v;
  }
  Mat36 PerJoint(double sigma) {
    Mat36 m;
    for (int i = 0; i < 6; ++i) {
      for (int a = 0; a < 3; ++a) m(a, i) = Signed(0.2 * sigma, sigma);
    }
    return m;
  }

 private:
  std::mt19937_64 rng_;
};

const std::vector<std::string>& Vocabulary() {
  static const std::vector<std::string> names = {
      "passive_rotation", "leg_offset", "joint_position", "lead_error",    "periodic_lead_error",
      "backlash",         "servo_lag",  "compliance",     "thermal_drift", "structural_resonance"};
  return names;
}

// Turns one effect of the vocabulary on; returns what was drawn.
std::string AddEffect(const std::string& name, Draw& d, BlindEffects* e) {
  if (name == "passive_rotation") {
    e->pr_override = true;
    e->true_pr_sign = d.Index(2) == 0 ? 0 : -1;
    return fmt::format("screws' true s = {}", e->true_pr_sign);
  }
  if (name == "leg_offset") {
    e->leg_offset_m = d.PerLeg(50e-6, 300e-6);
    return "leg offsets 50-300 um";
  }
  if (name == "joint_position") {
    e->base_joint_error_m = d.PerJoint(400e-6);
    e->platform_joint_error_m = d.PerJoint(400e-6);
    return "joint centres off by up to 0.4 mm per axis";
  }
  if (name == "lead_error") {
    e->lead_error = d.PerLeg(100e-6, 500e-6);
    return "lead errors 100-500 ppm";
  }
  if (name == "periodic_lead_error") {
    e->periodic_amplitude_m = d.PerLegPositive(8e-6, 25e-6);
    e->periodic_phase_rad = d.PerLegPositive(0.0, 2.0 * kPi);
    return "pitch error 8-25 um once per turn";
  }
  if (name == "backlash") {
    e->backlash_m = d.PerLegPositive(15e-6, 40e-6);
    return "backlash 15-40 um";
  }
  if (name == "servo_lag") {
    e->servo_bandwidth_hz = d.Uniform(10.0, 30.0);
    return fmt::format("servo bandwidth {:.1f} Hz", e->servo_bandwidth_hz);
  }
  if (name == "compliance") {
    e->stiffness_N_m = d.PerLegPositive(2e7, 6e7);
    e->mass_kg = d.Uniform(400.0, 900.0);
    e->com_M = Vec3(d.Signed(0.0, 0.1), d.Signed(0.0, 0.1), d.Uniform(0.05, 0.3));
    return fmt::format("legs 20-60 N/um, platform {:.0f} kg", e->mass_kg);
  }
  if (name == "structural_resonance") {
    e->resonance_hz = d.Uniform(3.0, 8.0);
    e->resonance_damping = d.Uniform(0.01, 0.05);
    e->resonance_gain = d.Uniform(0.4, 1.0);
    return fmt::format("structure sways at {:.1f} Hz, damping {:.3f}", e->resonance_hz, e->resonance_damping);
  }
  // thermal_drift: by travel or by time under power, time constant drawn.
  e->alpha_per_K = 11.7e-6;
  e->thermal_tau_s = d.Uniform(300.0, 1500.0);
  if (d.Index(2) == 0) {
    e->heating_K_per_m = d.Uniform(3.0, 8.0);
    return fmt::format("screws warm {:.1f} K/m of travel, tau {:.0f} s", e->heating_K_per_m, e->thermal_tau_s);
  }
  e->heating_K_per_s = d.Uniform(0.004, 0.012);
  return fmt::format("screws warm {:.1f} mK/s under power, tau {:.0f} s", e->heating_K_per_s * 1e3, e->thermal_tau_s);
}

std::string AddOutOfVocabulary(const std::string& kind, Draw& d, BlindEffects* e) {
  if (kind == "floor_vibration") {
    e->floor_hz = d.Uniform(2.0, 15.0);
    e->floor_amplitude_m = d.Uniform(15e-6, 40e-6);
    e->floor_direction = Vec3(d.Signed(0.2, 1.0), d.Signed(0.2, 1.0), d.Signed(0.0, 0.5));
    return fmt::format("tracker stand vibrates at {:.1f} Hz, {:.0f} um", e->floor_hz, e->floor_amplitude_m * 1e6);
  }
  if (kind == "stand_drift") {
    // The stand settles sideways (a tripod's feet, its own warming): 50-130 um over a session.
    const double angle = d.Uniform(0.0, 2.0 * kPi);
    e->stand_drift_m_per_s = d.Uniform(0.15e-6, 0.4e-6) * Vec3(std::cos(angle), std::sin(angle), d.Signed(0.0, 0.3));
    e->stand_settle_s = d.Uniform(200.0, 800.0);
    return fmt::format("tracker stand settles {:.2f} um/s, tau {:.0f} s", e->stand_drift_m_per_s.norm() * 1e6,
                       e->stand_settle_s);
  }
  if (kind == "clock_drift") {
    // The tracker's clock runs free of the controller's (no trigger, no
    // PTP): a quartz 1-4 ppm apart, 0.3-1.3 ms over a session.
    e->clock_drift = d.Uniform(1e-6, 4e-6);
    return fmt::format("tracker clock gains {:.1f} ppm", e->clock_drift * 1e6);
  }
  if (kind == "target_reseat") {
    // The target is taken out of its nest between runs and put back: a
    // seat that is not clean moves its centre 10-30 um each time.
    e->target_reseat_m = d.Uniform(10e-6, 30e-6);
    return fmt::format("tracker target re-seated before each run, {:.0f} um RMS", e->target_reseat_m * 1e6);
  }
  // base_tilt: the base mount gives under the platform's moment.
  e->mass_kg = d.Uniform(400.0, 900.0);
  e->com_M = Vec3(0.0, 0.0, 0.1);
  e->base_tilt_rad_per_N_m = d.Uniform(1.5e-8, 3e-8);
  return fmt::format("base mount tilts {:.1f} urad per kN m", e->base_tilt_rad_per_N_m * 1e9);
}

}  // namespace

BlindScenario DrawBlindWholeRig(std::uint64_t seed, int index, double payload_max_kg) {
  Draw d(seed * 0xbf58476d1ce4e5b9ULL + static_cast<std::uint64_t>(index) * 104729ULL + 3);
  BlindScenario s;
  s.kind = "whole_rig";
  s.truth = {"leg_offset", "joint_position", "lead_error", "periodic_lead_error", "backlash", "compliance"};
  BlindEffects& e = s.effects;
  e.leg_offset_m = d.PerLeg(0.0, 120e-6);
  std::normal_distribution<double> joint(0.0, 100e-6);
  std::mt19937_64 joints(seed ^ (static_cast<std::uint64_t>(index) << 20));
  for (int i = 0; i < 6; ++i) {
    for (int a = 0; a < 3; ++a) {
      e.base_joint_error_m(a, i) = joint(joints);
      e.platform_joint_error_m(a, i) = joint(joints);
    }
  }
  e.lead_error = d.PerLeg(0.0, 250e-6);
  e.periodic_amplitude_m = d.PerLegPositive(2e-6, 8e-6);
  e.periodic_phase_rad = d.PerLegPositive(0.0, 2.0 * kPi);
  e.backlash_m = d.PerLegPositive(15e-6, 40e-6);
  const double stiffness = d.Uniform(15e6, 30e6);  // one design of leg, assembled ±10%
  e.stiffness_N_m = stiffness * d.PerLegPositive(0.9, 1.1);
  e.mass_kg = d.Uniform(500.0, std::max(500.0, payload_max_kg));
  e.com_M = Vec3(0.0, 0.0, d.Uniform(0.0, 0.3));
  s.tracker.rate_hz = 100.0;
  s.tracker.noise_m = 5e-6;
  s.tracker.encoders = true;
  s.tracker.seed = seed * 131 + static_cast<std::uint64_t>(index);
  s.tracker.frame << d.Uniform(-3.0, 3.0), d.Uniform(-3.0, 3.0), d.Uniform(-0.5, 0.5), d.Signed(0.0, 0.03),
      d.Signed(0.0, 0.03), d.Uniform(-kPi, kPi);
  s.description = fmt::format("whole rig: {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/um legs", e.mass_kg, e.com_M.z(),
                              stiffness * 1e-6);
  return s;
}

BlindScenario DrawBlindEveryClassRig(std::uint64_t seed, int index, double payload_max_kg) {
  BlindScenario s = DrawBlindWholeRig(seed, index, payload_max_kg);
  Draw d(seed * 0x94d049bb133111ebULL + static_cast<std::uint64_t>(index) * 15485863ULL + 5);
  BlindEffects& e = s.effects;
  constexpr double kLightestKg = 100.0;
  e.mass_kg = d.LogUniform(kLightestKg, std::max(kLightestKg * 1.001, payload_max_kg));
  std::vector<std::string> parts = {fmt::format("every class: {:.0f} kg (c.o.m. {:.2f} m up) on {:.1f} N/um legs",
                                                e.mass_kg, e.com_M.z(), e.stiffness_N_m.mean() * 1e-6)};
  std::vector<std::string> dynamic = {"servo_lag", "thermal_drift"};
  if (d.Index(2) == 0) dynamic.push_back("passive_rotation");
  for (const std::string& name : dynamic) {
    s.truth.push_back(name);
    parts.push_back(AddEffect(name, d, &e));
  }
  s.description = fmt::format("{}", fmt::join(parts, "; "));
  return s;
}

std::vector<std::string> OutOfVocabularyKinds() {
  return {"floor_vibration", "base_tilt", "stand_drift", "clock_drift", "target_reseat"};
}

BlindScenario DrawBlindScenario(std::uint64_t seed, int index, std::optional<bool> encoders) {
  Draw d(seed * 0x9e3779b97f4a7c15ULL + static_cast<std::uint64_t>(index) * 7919ULL + 1);
  BlindScenario s;
  const int slot = index % 5;
  std::vector<std::string> parts;
  if (slot == 0) {
    s.kind = "none";
  } else if (slot <= 3) {
    s.kind = slot <= 2 ? "single" : "pair";
    std::vector<std::string> pool = Vocabulary();
    for (int k = 0; k < (slot <= 2 ? 1 : 2); ++k) {
      const int pick = d.Index(static_cast<int>(pool.size()));
      s.truth.push_back(pool[static_cast<std::size_t>(pick)]);
      pool.erase(pool.begin() + pick);
      parts.push_back(AddEffect(s.truth.back(), d, &s.effects));
    }
  } else {
    s.kind = "out_of_vocabulary";
    const std::vector<std::string> kinds = OutOfVocabularyKinds();
    s.truth.push_back(kinds[static_cast<std::size_t>(d.Index(static_cast<int>(kinds.size())))]);
    parts.push_back(AddOutOfVocabulary(s.truth.back(), d, &s.effects));
  }
  s.tracker.rate_hz = d.LogUniform(10.0, 1000.0);
  s.tracker.noise_m = d.Uniform(2e-6, 20e-6);
  s.tracker.encoders = d.Index(2) == 0;
  if (encoders) s.tracker.encoders = *encoders;
  s.tracker.seed = seed * 31 + static_cast<std::uint64_t>(index);
  s.tracker.frame << d.Uniform(-3.0, 3.0), d.Uniform(-3.0, 3.0), d.Uniform(-0.5, 0.5), d.Signed(0.0, 0.02),
      d.Signed(0.0, 0.02), d.Uniform(-kPi, kPi);
  parts.push_back(fmt::format("tracker {:.0f} Hz, {:.1f} um, {} encoders", s.tracker.rate_hz, s.tracker.noise_m * 1e6,
                              s.tracker.encoders ? "with" : "without"));
  for (const std::string& p : parts) s.description += (s.description.empty() ? "" : "; ") + p;
  return s;
}

}  // namespace edsp::blind
