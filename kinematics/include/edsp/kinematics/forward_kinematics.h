#pragma once
// Forward kinematics: the pose at which six legs have given lengths, by
// Newton–Raphson from an initial guess. With PR the legs' true lengths are the
// encoder-implied lengths plus the true signed PR error of the pose being
// sought, so that term (and its analytic derivative) is inside the iteration.
// It never returns a wrong answer silently: anything but kConverged says why.

#include "edsp/kinematics/platform_model.h"

namespace edsp {

enum class FkStatus {
  kConverged,         // residual ≤ tolerance, pose inside the joint limits
  kMaxIterations,     // iteration cap reached without meeting the tolerance
  kSingular,          // Jacobian too ill-conditioned to trust a step
  kDiverged,          // non-finite values or the step limit kept biting
  kOutsideWorkspace,  // converged to an assembly the joints cannot reach
  kInvalidInput,      // non-finite or non-positive lengths, non-finite guess
};

const char* FkStatusName(FkStatus status);

struct FkOptions {
  bool with_pr = true;  // model the screws' true signed PR
  int max_iterations = 30;
  double tolerance_m = 1e-12;  // max |leg length residual|
  double min_rcond = 1e-9;     // reciprocal condition estimate of the Jacobian
  double max_step_m = 0.1;     // per-iteration translation step limit
  double max_step_rad = 0.1;   // per-iteration rotation step limit
};

struct FkResult {
  FkStatus status = FkStatus::kInvalidInput;
  Pose pose;                // last iterate (the answer when kConverged)
  double residual_m = 0.0;  // max |length residual| at `pose`
  int iterations = 0;
  bool ok() const { return status == FkStatus::kConverged; }
};

FkResult SolveForward(const PlatformModel& model, const Vector6& lengths_m, const Pose& guess,
                      const FkOptions& options = {});

}  // namespace edsp
