// The stack composed in-process (planner → kinematics → bridge → virtual rig,
// tracker noise off): with signed compensation point A settles within 5 µm of
// its target at every dwell; with none it misses by the PR error edsp-sim
// predicts for that pose.
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/sim/paper_table.h"
#include "edsp/sim/stack_simulation.h"

namespace edsp {
namespace {

struct DwellResult {
  std::string segment;
  Pose target;
  double miss_m;  // |tracker A − target A| at the end of the dwell
};

std::vector<DwellResult> RunMotion(const std::string& motion, PrMode mode) {
  const PlatformConfig nominal = Huang2021Config();
  auto trajectory = std::make_unique<TrajectorySequence>();
  PaperMotionOptions options;
  options.stops = 3;
  options.dwell_s = 0.5;
  options.max_speed_m_s = 0.25;
  options.max_speed_rad_s = 0.5;
  AppendPaperMotion(motion, PlatformModel(nominal).home_pose().ToVector(), options, trajectory.get());
  StackOptions stack;
  stack.pr_mode = mode;
  StackSimulation sim(nominal, std::move(trajectory), stack);
  const PlatformModel& model = sim.nominal_model();
  std::vector<DwellResult> dwells;
  StackSample previous;
  bool have_previous = false;
  while (!sim.Finished()) {
    const StackSample s = sim.Step();
    // The last sample of each dwell: the segment changes after it.
    if (have_previous && previous.setpoint.segment != s.setpoint.segment &&
        previous.setpoint.phase == pose_setpoint_t::PHASE_DWELL) {
      Vector6 q;
      for (int k = 0; k < 6; ++k) q(k) = previous.setpoint.pose[k];
      const Vector3 target = model.ObservationPoint(Pose::FromVector(q));
      const Vector3 measured(previous.tracker.point_m[0], previous.tracker.point_m[1], previous.tracker.point_m[2]);
      dwells.push_back({previous.setpoint.trajectory, Pose::FromVector(q), (measured - target).norm()});
    }
    previous = s;
    have_previous = true;
  }
  EXPECT_TRUE(sim.faults().empty()) << sim.faults().front().reason;
  return dwells;
}

TEST(StackSimulation, SignedCompensationSettlesPointAWithin5umAtEveryDwell) {
  for (const std::string motion : {"Lz", "Rz"}) {
    const auto dwells = RunMotion(motion, PrMode::kSigned);
    ASSERT_EQ(dwells.size(), 3u) << motion;  // two of the three stops + home (last dwell ends the run)
    for (const DwellResult& d : dwells) EXPECT_LT(d.miss_m, 5e-6) << d.segment;
  }
}

TEST(StackSimulation, WithoutCompensationMissesByThePredictedPrError) {
  const PlatformModel model(Huang2021Config());
  for (const std::string motion : {"Lz", "Rz"}) {
    bool some_large_miss = false;
    for (const DwellResult& d : RunMotion(motion, PrMode::kNone)) {
      const double predicted = PointAError(model, d.target, PrMode::kNone);
      EXPECT_NEAR(d.miss_m, predicted, 5e-7) << d.segment;
      some_large_miss = some_large_miss || predicted > 1e-4;
    }
    EXPECT_TRUE(some_large_miss) << motion;
  }
}

}  // namespace
}  // namespace edsp
