#pragma once
// The residual's structure as a nuisance (residual_structure.h): columns
// that can take up a mode at the structure's frequency, whatever drives it.
// An effect whose held-out gain survives only without them is one the
// structure could also explain, and is not called identified (diagnose.h).
//   - a lightly damped mode driven by A's acceleration (a sway of the
//     structure carrying A): per axis of {B}, the mode's response to A's
//     acceleration on that axis;
//   - a sinusoid at the same frequency in the tracker's frame (the
//     tracker's stand vibrating), in phase and quadrature per axis.

#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/residual_structure.h"

namespace edsp::gap {

// Modes tried: the structure's own peak (when above the motions' rates)
// and a grid over the band where platforms and their mounts ring; the
// tracker's rate need not resolve them (the quasi-static response to
// acceleration is what a slow tracker sees).
std::vector<double> CandidateModeFrequencies(const ResidualStructure& structure);
inline constexpr double kAssumedDamping = 0.03;

// 9 columns, 3 rows per sample of `d`: the mode at `hz` with damping `zeta`.
Eigen::MatrixXd StructureColumns(const Design& d, double hz, double zeta);

// `d` with `extra` as nuisance beside the frame: the columns are
// [frame | extra | effects], and the frame's range covers both, so every fit
// of the design estimates them with the frame.
Design WithNuisance(const Design& d, const Eigen::MatrixXd& extra);

}  // namespace edsp::gap
