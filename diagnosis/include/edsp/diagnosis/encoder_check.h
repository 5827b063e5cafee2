#pragma once
// Does the lag the tracker sees lie in the drives? A servo lag lies between
// the command and the motor, so with encoder columns the drives' own
// tracking error (command − encoder) must show it. A lag the encoders do not
// show lies after the motor: a structure swaying under the platform's
// acceleration looks, below its resonance, like the drives' acceleration
// lag on every leg. Such a servo_lag is not identified (beyond_vocabulary.h).

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

// Share of the fitted servo_lag's motion of A (its columns × θ) that the
// encoders' tracking error accounts for: its projection on the fit,
// fit·encoders / |fit|², at most 1 (encoders that show more lag than the
// fit recovered are the drives' all the same); 1 without encoder columns
// (nothing to check against).
double EncoderShareOfLag(const Design& design, const Eigen::VectorXd& servo_lag_theta);

// Below this share the lag is not the drives'.
inline constexpr double kMinEncoderShareOfLag = 0.5;

}  // namespace edsp::gap
