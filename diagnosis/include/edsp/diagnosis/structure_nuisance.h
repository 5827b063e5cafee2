#pragma once
// Structure outside the vocabulary as a nuisance: columns that can take up
// a mode at the residual's frequency (residual_structure.h), whatever drives
// it, or a base that tilts under the payload's moment. An effect whose held-out
// gain survives only without them is one the structure could also explain,
// and is not called identified (beyond_vocabulary.h).
//   - a lightly damped mode driven by A's acceleration (a sway of the
//     structure carrying A): per axis of {B}, the mode's response to A's
//     acceleration on that axis;
//   - a sinusoid at the same frequency in the tracker's frame (the
//     tracker's stand vibrating), in phase and quadrature per axis, on the
//     data's clock: it predicts a held-out run only for a vibration that
//     keeps its phase over the session, as a stand ringing steadily does.

#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/residual_structure.h"

namespace edsp::gap {

// Modes tried: the structure's own peak when it lies above 1 Hz (below, it
// is the motions' own rate) and a grid over the band where platforms and
// their mounts ring; the tracker's rate need not resolve them (the
// quasi-static response to acceleration is what a slow tracker sees).
std::vector<double> CandidateModeFrequencies(const ResidualStructure& structure);
// A light damping, whatever the spectrum's peak says: its half-power width
// is often unresolved, and the mode's response below resonance hardly
// depends on it.
inline constexpr double kAssumedDamping = 0.03;

// 3 columns, 3 rows per sample of `d`: A's sway along x, y, z of {B} for a
// mode at `hz` with damping `zeta` at unit gain, in the tracker's frame: the
// structural_resonance effect's columns at that mode.
Eigen::MatrixXd SwayColumns(const Design& d, double hz, double zeta);

// 9 columns: the sway's, then the tracker's vibration at `hz`.
Eigen::MatrixXd StructureColumns(const Design& d, double hz, double zeta);

// 24 columns: the base tilting under the moment the payload's weight and
// translational inertia put on it, δθ = C·M with C a symmetric rotational compliance and
// M = m·(M₀ + Σ c_a·M_a) (design.h's load_moment_per_kg) for a payload of
// unknown mass m and c.o.m. c: C·m and C·m·c_a as 4 × 6 free terms; A
// turns with the base about {B}'s origin (a mount pivoting elsewhere adds
// a translation the frame does not take up). A base mount or floor that gives
// moves every leg at once, which the legs' own compliance (each leg under
// its own load) and joint centres take up only in part.
Eigen::MatrixXd BaseTiltColumns(const Design& d);

// `d` with `extra` as its nuisance: the columns are [frame | extra |
// effects], and every fit of the design (linear_fit.h) estimates them with
// the frame.
Design WithNuisance(const Design& d, const Eigen::MatrixXd& extra);

}  // namespace edsp::gap
