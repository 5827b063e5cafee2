#include "edsp/kinematics/forward_kinematics.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "edsp/kinematics/workspace.h"

namespace edsp {

const char* FkStatusName(FkStatus status) {
  switch (status) {
    case FkStatus::kConverged: return "converged";
    case FkStatus::kMaxIterations: return "iteration cap reached";
    case FkStatus::kSingular: return "singular Jacobian";
    case FkStatus::kDiverged: return "diverged";
    case FkStatus::kOutsideWorkspace: return "converged outside the joint limits";
    case FkStatus::kInvalidInput: return "invalid input";
  }
  return "invalid status";
}

namespace {

// Leg lengths as the encoders see them at q: with PR, the true length minus
// the true PR error (what forward kinematics must match).
Vector6 ModelledLengths(const PlatformModel& model, const LegSolution& legs, bool with_pr) {
  return with_pr ? Vector6(legs.length_m - model.PrLengthError(legs, PrMode::kSigned)) : legs.length_m;
}

// Shrinks a Newton step to the per-iteration limits; far from the solution a
// full step can jump to another assembly mode.
Vector6 LimitStep(const Vector6& step, const FkOptions& options) {
  const double translation = step.head<3>().norm();
  const double rotation = step.tail<3>().norm();
  const double scale = std::min(
      {1.0, options.max_step_m / std::max(translation, 1e-300), options.max_step_rad / std::max(rotation, 1e-300)});
  return scale * step;
}

bool ValidInput(const Vector6& lengths_m, const Pose& guess) {
  return lengths_m.allFinite() && (lengths_m.array() > 0.0).all() && guess.IsFinite();
}

}  // namespace

FkResult SolveForward(const PlatformModel& model, const Vector6& lengths_m, const Pose& guess,
                      const FkOptions& options) {
  FkResult result;
  result.pose = guess;
  if (!ValidInput(lengths_m, guess)) return result;

  Vector6 q = guess.ToVector();
  for (result.iterations = 0; result.iterations <= options.max_iterations; ++result.iterations) {
    result.pose = Pose::FromVector(q);
    const LegSolution legs = model.Solve(result.pose);
    const Vector6 residual = ModelledLengths(model, legs, options.with_pr) - lengths_m;
    result.residual_m = residual.cwiseAbs().maxCoeff();
    if (!std::isfinite(result.residual_m)) {
      result.status = FkStatus::kDiverged;
      return result;
    }
    if (result.residual_m <= options.tolerance_m) {
      result.status = CheckJointAngles(model, legs).ok() ? FkStatus::kConverged : FkStatus::kOutsideWorkspace;
      return result;
    }
    if (result.iterations == options.max_iterations) break;
    Matrix6 J, pr_jacobian;
    model.Jacobians(result.pose, legs, &J, options.with_pr ? &pr_jacobian : nullptr);
    if (options.with_pr) J -= pr_jacobian;
    const Eigen::PartialPivLU<Matrix6> lu(J);
    if (!(lu.rcond() >= options.min_rcond)) {
      result.status = FkStatus::kSingular;
      return result;
    }
    q -= LimitStep(lu.solve(residual), options);
  }
  result.status = FkStatus::kMaxIterations;
  return result;
}

}  // namespace edsp
