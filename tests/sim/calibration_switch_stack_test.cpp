// A calibration switched on while the stack moves (what `edsp-ctl
// calibration` does live), on the stack's own classes against the virtual
// rig's physics of the effect, which are written apart from the model the
// calibration applies (rig/ against kinematics/leg_error_model): the bridge
// sees no step (no fault), the dwells before the switch miss as the
// uncalibrated stack's do, and every dwell after the blend lands where the
// stack calibrated from the start lands, at the tracker's noise.
#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/sim/stack_simulation.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

std::string Config() { return SourcePath("config/huang2021-rig-effects.toml"); }

// The example rig's leg offsets, three times over by default (about 0.3 mm
// at A), or scaled until the largest is `largest_m`.
RigEffects Offsets(double largest_m = 0.0) {
  RigEffects e = OnlyEffect(LoadRigEffects(Config()), calibration::Effect::kLegOffset);
  double largest = 0.0;
  for (double v : e.leg_offset.offset_m) largest = std::max(largest, std::abs(v));
  const double scale = largest_m > 0.0 ? largest_m / largest : 3.0;
  for (double& v : e.leg_offset.offset_m) v *= scale;
  return e;
}

// The model a calibration would identify, written by hand from the rig's
// parameters: each leg is that much longer than its encoder says.
calibration::CalibrationModel HandModel(const PlatformModel& model, double largest_m = 0.0) {
  const RigEffects e = Offsets(largest_m);
  const std::string json = fmt::format(
      R"({{"format": "edsp-gap-model/1", "effects": [{{"name": "leg_offset", "verdict": "identified",
          "theta": [{}]}}]}})",
      fmt::join(e.leg_offset.offset_m, ", "));
  return calibration::ParseCalibration(json, "hand.json", model);
}

struct StackRun {
  std::vector<double> dwell_miss_m;  // |tracker A − target A| at the end of each dwell
  std::vector<std::int64_t> dwell_end_utime;
  std::vector<std::array<double, 6>> commands;  // every cycle's leg command (m)
  std::vector<fault_t> faults;
  std::int64_t switched_at_utime = -1;
};

// The largest change from one cycle to the next of what `run` commands
// beyond `reference` (the correction), and the largest correction.
std::pair<double, double> CorrectionSteps(const StackRun& run, const StackRun& reference) {
  double largest_step = 0.0, largest = 0.0;
  for (std::size_t k = 1; k < std::min(run.commands.size(), reference.commands.size()); ++k) {
    for (std::size_t i = 0; i < 6; ++i) {
      const double now = run.commands[k][i] - reference.commands[k][i];
      const double before = run.commands[k - 1][i] - reference.commands[k - 1][i];
      largest_step = std::max(largest_step, std::abs(now - before));
      largest = std::max(largest, std::abs(now));
    }
  }
  return {largest_step, largest};
}

enum class Calibration { kNone, kFromStart, kSwitchedOnMidMotion };

StackRun RunLx(Calibration calibration, double largest_offset_m = 0.0) {
  const PlatformConfig nominal = LoadConfigFile(Config());
  const PlatformModel model(nominal);
  auto trajectory = std::make_unique<TrajectorySequence>();
  PaperMotionOptions motion;
  motion.stops = 4;
  motion.dwell_s = 0.4;
  motion.max_speed_m_s = 0.25;
  AppendPaperMotion("Lx", model.home_pose().ToVector(), motion, trajectory.get());
  StackOptions options;
  options.rig = IdealRig(nominal);
  options.rig->effects = Offsets(largest_offset_m);
  if (calibration == Calibration::kFromStart) options.calibration = HandModel(model, largest_offset_m);
  StackSimulation sim(nominal, std::move(trajectory), options);

  StackRun run;
  StackSample previous;
  bool have_previous = false, past_first_dwell = false;
  while (!sim.Finished()) {
    const StackSample s = sim.Step();
    EXPECT_TRUE(s.command_valid);
    run.commands.push_back({});
    std::copy(s.command.command_length_m, s.command.command_length_m + 6, run.commands.back().begin());
    const bool dwell_ended = have_previous && previous.setpoint.segment != s.setpoint.segment &&
                             previous.setpoint.phase == pose_setpoint_t::PHASE_DWELL;
    if (dwell_ended) {
      Vector6 q;
      for (int k = 0; k < 6; ++k) q(k) = previous.setpoint.pose[k];
      const Vector3 target = model.ObservationPoint(Pose::FromVector(q));
      const Vector3 measured(previous.tracker.point_m[0], previous.tracker.point_m[1], previous.tracker.point_m[2]);
      run.dwell_miss_m.push_back((measured - target).norm());
      run.dwell_end_utime.push_back(previous.setpoint.utime);
      past_first_dwell = true;
    }
    // Mid-move after the first dwell, at speed: the hardest moment to switch.
    if (calibration == Calibration::kSwitchedOnMidMotion && past_first_dwell && run.switched_at_utime < 0 &&
        std::abs(s.setpoint.velocity[0]) > 0.2) {
      std::string why_not;
      EXPECT_TRUE(sim.kinematics().SwitchCalibration(HandModel(model), &why_not)) << why_not;
      run.switched_at_utime = s.setpoint.utime;
    }
    previous = s;
    have_previous = true;
  }
  run.faults = sim.faults();
  return run;
}

TEST(CalibrationSwitchStack, SwitchedOnMidMotionTheDwellsAfterTheBlendLandAsCalibratedFromTheStart) {
  const StackRun none = RunLx(Calibration::kNone), from_start = RunLx(Calibration::kFromStart),
                 switched = RunLx(Calibration::kSwitchedOnMidMotion);
  ASSERT_GE(none.dwell_miss_m.size(), 4u);
  ASSERT_EQ(switched.dwell_miss_m.size(), none.dwell_miss_m.size());
  ASSERT_EQ(from_start.dwell_miss_m.size(), none.dwell_miss_m.size());
  ASSERT_GT(switched.switched_at_utime, 0);
  for (const StackRun* r : {&none, &from_start, &switched}) {
    EXPECT_TRUE(r->faults.empty()) << r->faults.front().reason;  // a step would be refused as a jump
  }
  const std::int64_t blend_over = switched.switched_at_utime + KinematicsNodeOptions{}.calibration_blend_us;
  int before = 0, after = 0;
  for (std::size_t d = 0; d < none.dwell_miss_m.size(); ++d) {
    const std::string what =
        fmt::format("dwell {}: none {:.2f} um, from the start {:.2f} um, switched {:.2f} um", d,
                    none.dwell_miss_m[d] * 1e6, from_start.dwell_miss_m[d] * 1e6, switched.dwell_miss_m[d] * 1e6);
    std::printf("SWITCH_ROW | %s\n", what.c_str());
    // The rig's offsets alone miss by far more than the calibrated stack.
    EXPECT_GT(none.dwell_miss_m[d], 50e-6) << what;
    EXPECT_LT(from_start.dwell_miss_m[d], 2e-6) << what;
    if (switched.dwell_end_utime[d] < switched.switched_at_utime) {
      EXPECT_NEAR(switched.dwell_miss_m[d], none.dwell_miss_m[d], 1e-8) << what;
      ++before;
    } else if (switched.dwell_end_utime[d] > blend_over) {
      EXPECT_NEAR(switched.dwell_miss_m[d], from_start.dwell_miss_m[d], 1e-7) << what;
      ++after;
    }
  }
  EXPECT_GE(before, 1);
  EXPECT_GE(after, 2);
  // Unblended, the whole correction would reach the drives in one cycle
  // (the bridge takes 0.3 mm on top of a 0.25 m/s move); blended over 1 s,
  // a cycle carries 1/1000 of it.
  const auto [largest_step, largest] = CorrectionSteps(switched, none);
  EXPECT_GT(largest, 100e-6);
  EXPECT_LT(largest_step, 2.0 * largest / 1000.0) << "largest " << largest * 1e6 << " um";
}

// Offsets of millimetres at home (a whole rig's offsets and joint centres
// add up to that): a calibration in force from the start steps every leg by
// its correction, far past the bridge's jump in a cycle. It blends in from
// where the drives hold instead, at home before the motions: nothing is
// refused, the run begins calibrated, and every dwell lands.
TEST(CalibrationSwitchStack, ACalibrationOfMillimetresAtHomeStartsFromTheDrivesAndEveryDwellLands) {
  constexpr double kLargestOffsetM = 4e-3;
  const StackRun none = RunLx(Calibration::kNone, kLargestOffsetM),
                 from_start = RunLx(Calibration::kFromStart, kLargestOffsetM);
  EXPECT_TRUE(from_start.faults.empty()) << from_start.faults.front().reason;
  ASSERT_GE(from_start.dwell_miss_m.size(), 4u);
  for (std::size_t d = 0; d < from_start.dwell_miss_m.size(); ++d) {
    EXPECT_GT(none.dwell_miss_m[d], 1e-3) << "dwell " << d;
    EXPECT_LT(from_start.dwell_miss_m[d], 2e-6) << "dwell " << d;
  }
  double first_correction = 0.0;
  for (std::size_t i = 0; i < 6; ++i) {
    first_correction = std::max(first_correction, std::abs(from_start.commands[0][i] - none.commands[0][i]));
  }
  EXPECT_GT(first_correction, 3e-3) << "the motions begin calibrated";
}

}  // namespace
}  // namespace edsp
