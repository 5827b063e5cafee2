#pragma once
// The structural_resonance effect's frequency and damping: the one pair of
// its parameters the residual is not linear in (its gains are). Chosen as
// the mode whose sway, beside the tracker frame and the effects already
// selected, predicts the held-out runs best: a grid over the band where
// platforms and their mounts ring, the residual's own spectral peak, then a
// golden-section refinement of the frequency and a choice of damping. Each
// candidate costs one small fit (the frame, the selected effects and the
// mode's three columns), not a diagnosis.

#include <vector>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct StructuralModeChoice {
  double hz = 0.0, damping = 0.0;
  double cv_gain = 0.0;  // the mode's cut of the held-out MSE beside the selected effects
};

// `sigma2`: the effects' prior's measurement variance (linear_fit.h's
// PriorWeights); `peak_hz`: the residual's spectral peak, 0 for none.
StructuralModeChoice ChooseStructuralMode(const Design& d, const std::vector<Effect>& selected, double sigma2,
                                          double peak_hz);

}  // namespace edsp::gap
