// The planner's motion service in process (targets on a 2-core machine):
//   the whole-path check of a 10 s move      ≤ 5 ms
//   a halt request handled                    (its cost; the reaction is the next cycle)
//   one cycle's setpoint while moving         (its cost at 1 kHz)
// Run: deploy/edsp bench motion   (medians over repetitions, JSON with --json)
#include <benchmark/benchmark.h>

#include "edsp/kinematics/config.h"
#include "edsp/planner/motion_service.h"

namespace edsp {
namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000;

// From x = −0.45 m to +0.45 m while turning 0.3 rad in yaw about a pivot
// 0.3 m above {M}: 0.9 m at 0.09 m/s, 10.3 s of motion.
PlannedMotion TenSecondMove(const PlatformModel& model) {
  Pose from = model.home_pose();
  from.p_BoMo_B.x() = -0.45;
  FramedPose to;
  to.t = Vector3(0.45, 0.0, model.home_pose().p_BoMo_B.z());
  to.R = RotationFromRpy(Vector3(0.0, 0.0, 0.3));
  MoveLimits limits = ConfigMoveLimits(model);
  limits.speed_m_s = 0.09;
  return PlanMove(model, WorkFrame{}, Vector3(0.0, 0.0, 0.3), TransformOf(from), to, limits, 1000.0);
}

void BM_CheckTenSecondPath(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  const PlannedMotion move = TenSecondMove(model);
  if (!move.check.ok()) state.SkipWithError(move.check.Describe().c_str());
  for (auto _ : state) {
    const PathCheck check = CheckPath(
        model, PathLimitsOf(model), [&](double t) { return move.path->PoseAt(MotionState(move, t).position); },
        move.duration_s(), 1000.0);
    benchmark::DoNotOptimize(check);
  }
  state.counters["path_s"] = move.duration_s();
}
BENCHMARK(BM_CheckTenSecondPath)->Unit(benchmark::kMillisecond);

void BM_PlanAndCheckTenSecondMove(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  for (auto _ : state) benchmark::DoNotOptimize(TenSecondMove(model));
}
BENCHMARK(BM_PlanAndCheckTenSecondMove)->Unit(benchmark::kMillisecond);

MotionServiceOptions Options() {
  MotionServiceOptions o;
  o.session_id = 1;
  return o;
}

motion_request_t Request(std::int8_t kind, std::int64_t id, std::int64_t now) {
  motion_request_t r{};
  r.utime = now;
  r.session_id = 1;
  r.request_id = id;
  r.kind = kind;
  return r;
}

void BM_StepWhileMoving(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  MotionService service(model, Options());
  leg_state_t legs{};
  for (auto& d : legs.drive_status) d = leg_state_t::DRIVE_ENABLED;
  std::int64_t now = kT0, id = 0;
  service.OnLegState(legs, now);
  for (auto _ : state) {
    if (!service.busy()) {  // rarely: a move lasts over a thousand cycles
      state.PauseTiming();
      motion_request_t move = Request(motion_request_t::KIND_MOVE, ++id, now);
      move.relative = true;
      move.pose[0] = id % 2 == 0 ? 0.05 : -0.05;
      service.OnLegState(legs, now);
      service.Handle(move, now);
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(service.Step(now));
    now += 1000;
  }
}
BENCHMARK(BM_StepWhileMoving)->Unit(benchmark::kMicrosecond);

void BM_HaltRequest(benchmark::State& state) {
  const PlatformModel model(Huang2021Config());
  leg_state_t legs{};
  for (auto& d : legs.drive_status) d = leg_state_t::DRIVE_ENABLED;
  std::int64_t id = 0;
  for (auto _ : state) {
    state.PauseTiming();
    MotionService service(model, Options());
    std::int64_t now = kT0;
    service.OnLegState(legs, now);
    motion_request_t move = Request(motion_request_t::KIND_MOVE, ++id, now);
    move.relative = true;
    move.pose[0] = 0.2;
    service.Handle(move, now);
    for (int k = 0; k < 1000; ++k) service.Step(now += 1000);
    const motion_request_t halt = Request(motion_request_t::KIND_HALT, ++id, now);
    state.ResumeTiming();
    benchmark::DoNotOptimize(service.Handle(halt, now));
  }
}
// Each halt needs a move at full speed first (paused): a fixed count keeps it short.
BENCHMARK(BM_HaltRequest)->Unit(benchmark::kMicrosecond)->Iterations(300);

}  // namespace
}  // namespace edsp

BENCHMARK_MAIN();
