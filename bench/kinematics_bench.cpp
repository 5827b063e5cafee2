// Kinematics speed (issue targets on a 2-core machine, one core):
//   IK + signed PR + compensation  ≥ 2 million poses/s
//   forward kinematics with PR     ≤ 5 µs median per solve
// Run: deploy/edsp bench   (medians over repetitions, JSON with --json)
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {
namespace {

// A fixed pool of workspace poses, cycled so the branch predictor and caches
// see realistic variety rather than one pose.
std::vector<Pose> PosePool(const PlatformModel& model, std::size_t count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> t(-0.4, 0.4), r(-0.4, 0.4);
  std::vector<Pose> poses;
  while (poses.size() < count) {
    Pose pose = model.home_pose();
    for (int k = 0; k < 3; ++k) pose.p_BoMo_B(k) += t(rng);
    for (int k = 0; k < 3; ++k) pose.rpy_rad(k) += r(rng);
    if (CheckWorkspace(model, pose).ok()) poses.push_back(pose);
  }
  return poses;
}

void BM_InverseKinematicsPrCompensation(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  const auto mode = static_cast<PrMode>(state.range(0));
  const std::vector<Pose> poses = PosePool(model, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.CompensatedLengths(poses[i], mode));
    i = (i + 1) & 1023;
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(PrModeName(mode));
}
BENCHMARK(BM_InverseKinematicsPrCompensation)
    ->Arg(static_cast<int>(PrMode::kSigned))
    ->Arg(static_cast<int>(PrMode::kUnsigned))
    ->Arg(static_cast<int>(PrMode::kNone));

void BM_InverseKinematicsOnly(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  const std::vector<Pose> poses = PosePool(model, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.LegLengths(poses[i]));
    i = (i + 1) & 1023;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InverseKinematicsOnly);

// Forward kinematics with PR from a guess a servo cycle away (the real-time
// case: last cycle's pose) and from home (a cold start).
void BM_ForwardKinematicsWithPr(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  const bool cold = state.range(0) != 0;
  const std::vector<Pose> poses = PosePool(model, 256);
  std::vector<Vector6> lengths;
  std::vector<Pose> guesses;
  for (const Pose& pose : poses) {
    lengths.push_back(model.EncoderLengths(pose));
    Pose guess = cold ? model.home_pose() : pose;
    if (!cold) {
      guess.p_BoMo_B.array() += 1e-4;  // 0.1 m/s for 1 ms
      guess.rpy_rad.array() -= 1e-4;
    }
    guesses.push_back(guess);
  }
  std::size_t i = 0, failures = 0;
  for (auto _ : state) {
    const FkResult fk = SolveForward(model, lengths[i], guesses[i]);
    failures += fk.ok() ? 0 : 1;
    benchmark::DoNotOptimize(fk);
    i = (i + 1) & 255;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["failures"] = static_cast<double>(failures);
  if (failures > 0) state.SkipWithError("forward kinematics failed");
  state.SetLabel(cold ? "from home" : "from last cycle");
}
BENCHMARK(BM_ForwardKinematicsWithPr)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace edsp

BENCHMARK_MAIN();
