// Inverse kinematics at home and at a displaced pose for an installed config,
// each leg finite and within its stroke, then forward kinematics back to the
// pose: what a program linking edsp::kinematics from an install can do.
//   edsp_consumer CONFIG.toml      exits 0 when all holds, 1 naming what does not
#include <cmath>
#include <cstdio>
#include <exception>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/platform_model.h"

namespace {

bool LegsWithinStroke(const edsp::PlatformModel& model, const edsp::Pose& pose, const char* what) {
  const edsp::Vector6 lengths = model.LegLengths(pose);
  const edsp::WorkspaceLimits& limits = model.config().limits;
  bool ok = true;
  for (int i = 0; i < 6; ++i) {
    const double l = lengths[i];
    std::printf("%s: leg %d %.6f m\n", what, i + 1, l);
    if (!std::isfinite(l) || l < limits.leg_min_m || l > limits.leg_max_m) {
      std::fprintf(stderr, "%s: leg %d length %g m outside [%g, %g] m\n", what, i + 1, l, limits.leg_min_m,
                   limits.leg_max_m);
      ok = false;
    }
  }
  return ok;
}

// FK from the encoder lengths at `pose` (the screws' signed PR modelled)
// must find `pose` again, from home as the guess.
bool RoundTrip(const edsp::PlatformModel& model, const edsp::Pose& pose, const char* what) {
  const edsp::FkResult fk = edsp::SolveForward(model, model.EncoderLengths(pose), model.home_pose());
  const double error = (fk.pose.ToVector() - pose.ToVector()).cwiseAbs().maxCoeff();
  std::printf("%s: FK %s in %d iterations, max |pose error| %.3g\n", what, edsp::FkStatusName(fk.status), fk.iterations,
              error);
  if (!fk.ok() || !(error < 1e-9)) {
    std::fprintf(stderr, "%s: forward kinematics did not return the pose (%s, error %g)\n", what,
                 edsp::FkStatusName(fk.status), error);
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CONFIG.toml\n", argv[0]);
    return 2;
  }
  try {
    const edsp::PlatformModel model(edsp::LoadConfigFile(argv[1]));
    edsp::Vector6 q;
    q << 0.1, -0.05, 1.6, 0.05, -0.03, 0.2;
    const edsp::Pose displaced = edsp::Pose::FromVector(q);
    bool ok = LegsWithinStroke(model, model.home_pose(), "home");
    ok = LegsWithinStroke(model, displaced, "displaced") && ok;
    ok = RoundTrip(model, displaced, "displaced") && ok;
    std::printf("%s\n", ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp_consumer: %s\n", e.what());
    return 1;
  }
}
