#include "edsp/sim/played_poses.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/sim/stack_simulation.h"

namespace edsp {
namespace {

// The samples as a trajectory: linear between them, the velocity of each
// interval (the kinematics' feed-forward), no acceleration.
class SampledPoses final : public Trajectory {
 public:
  SampledPoses(const std::vector<Pose>& poses, double period_s) : period_s_(period_s) {
    poses_.reserve(poses.size());
    for (const Pose& pose : poses) poses_.push_back(pose.ToVector());
  }
  double duration_s() const override { return static_cast<double>(poses_.size() - 1) * period_s_; }
  PoseSample Sample(double t_s) const override {
    PoseSample sample;
    const double at = std::clamp(t_s / period_s_, 0.0, static_cast<double>(poses_.size() - 1));
    const auto k = std::min(static_cast<std::size_t>(at), poses_.size() - 2);
    const double w = at - static_cast<double>(k);
    sample.pose = (1.0 - w) * poses_[k] + w * poses_[k + 1];
    sample.velocity = (poses_[k + 1] - poses_[k]) / period_s_;
    return sample;
  }

 private:
  std::vector<Vector6> poses_;
  double period_s_;
};

}  // namespace

std::vector<Pose> PlayPosesThroughTheStack(const PlatformConfig& nominal, const RigEffects& effects,
                                           const std::vector<Pose>& poses, double period_s) {
  StackOptions options;
  if (poses.size() < 2) throw std::invalid_argument("a played path needs at least 2 poses");
  if (std::fabs(period_s - options.cycle_s) > 1e-12) {
    throw std::invalid_argument(
        fmt::format("poses every {} s: the stack plays one per cycle ({} s)", period_s, options.cycle_s));
  }
  RigParameters rig = IdealRig(nominal);
  rig.effects = effects;
  options.rig = rig;
  auto path = std::make_unique<TrajectorySequence>();
  path->Append("played", std::make_unique<SampledPoses>(poses, period_s));
  StackSimulation stack(nominal, std::move(path), options);
  // A step commands sample k and leaves the rig at the next instant: the
  // truth after step k − 1 is where the platform is at sample k.
  std::vector<Pose> truth;
  truth.reserve(poses.size());
  truth.push_back(poses.front());
  while (truth.size() < poses.size() && !stack.Finished()) {
    const StackSample s = stack.Step();
    if (!stack.faults().empty()) {
      throw std::runtime_error(fmt::format("the stack refused the played path at sample {}: {}", truth.size(),
                                           stack.faults().front().reason));
    }
    Vector6 q;
    for (int i = 0; i < 6; ++i) q(i) = s.truth.pose[i];
    truth.push_back(Pose::FromVector(q));
  }
  while (truth.size() < poses.size()) truth.push_back(truth.back());
  return truth;
}

}  // namespace edsp
