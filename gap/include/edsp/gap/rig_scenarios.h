#pragma once
// The benchmark's scenarios on edsp's own rig: which effects of the
// vocabulary a scenario's rig has, drawn with realistic magnitudes for a
// platform of the paper's size (docs/rig.md), and how its controller
// compensates the passive rotation.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "edsp/diagnosis/effects.h"
#include "edsp/kinematics/passive_rotation.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/kinematics/pose.h"
#include "edsp/rig/rig_effects.h"

namespace edsp::gap {

// One drawn scenario: what the rig really does, and how the controller compensates.
struct Scenario {
  std::vector<Effect> truth;
  RigEffects effects;
  PrMode compensation = PrMode::kSigned;
  std::string description;
};

// Scenario k of a seed: k % 5 == 0 effect-free, 1–2 one effect, 3–4 two.
Scenario DrawScenario(std::uint64_t seed, int index);

// Rig k of a seed with every static effect class at once, as a real rig
// has them: leg offsets ±120 µm, joint centres σ 100 µm, leads ±250 ppm,
// backlash 15–40 µm, periodic lead error 2–8 µm, legs of 15–30 N/µm under
// a payload from 500 kg up to `rated_payload_kg` (centre of mass 0–0.3 m
// above {M}), a drive loop of 30–80 Hz with integral action. `truth` lists
// them all. RatePayload (rig/payload_rating.h) gives the rating; the draw
// takes the centre of mass it was rated for, 0.3 m up (the worst drawn).
Scenario DrawWholeRig(std::uint64_t seed, int index, double rated_payload_kg);
inline constexpr double kWholeRigComHeightMaxM = 0.3;
// The payload the whole rigs are drawn up to: the drives' rating
// (RatePayload) at the highest centre of mass drawn.
double WholeRigRatedPayload(const PlatformModel& model);

// Rig k of a seed with every class at once: DrawWholeRig's static ones and
// its play, compliance and drive loop, but the loop a soft one (servo lag,
// 8–20 Hz, integral action as DrawWholeRig's), screws warming with travel (thermal
// drift), half the rigs with a passive rotation the controller gets wrong
// (DrawScenario's draws), and payloads from light to heavy (log-uniform from
// kEveryClassPayloadMinKg up to `rated_payload_kg`). `truth` lists them all.
Scenario DrawEveryClassRig(std::uint64_t seed, int index, double rated_payload_kg);
inline constexpr double kEveryClassPayloadMinKg = 100.0;

// Where the tracker stands, X_TB: anywhere on the floor within 3 m, turned
// any way about z, tilted up to 0.03 rad.
Pose DrawTrackerStand(std::mt19937_64& rng);

}  // namespace edsp::gap
