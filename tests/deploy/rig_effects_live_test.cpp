// The live sim group on a rig with every effect of the example config (the
// edsp-rig process reads [rig.effects] from the group's config) measures at
// its stops what `edsp-sim rig` computes offline for the same motions: the
// offline dataset stands for the live one.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "sim_group_harness.h"
#include "edsp/channels.h"
#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/rig_truth_t.hpp"
#include "edsp/sim/dwell_errors.h"
#include "edsp/sim/offline_run.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

// What the virtual rig says it did over a dwell's averaging window: point A
// and the legs, as they truly were, averaged.
struct DwellTruth {
  Vector3 point_m = Vector3::Zero();
  Vector6 leg_length_m = Vector6::Zero();
};

std::vector<DwellTruth> DwellTruths(const std::string& log_path, const std::vector<DwellError>& dwells) {
  std::vector<DwellTruth> truths(dwells.size());
  std::vector<int> counts(dwells.size(), 0);
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    rig_truth_t t;
    if (event.channel != channel::kRigTruth ||
        t.decode(event.data.data(), 0, static_cast<int>(event.data.size())) < 0) {
      continue;
    }
    for (std::size_t k = 0; k < dwells.size(); ++k) {
      if (t.utime < dwells[k].averaged_from_utime || t.utime > dwells[k].averaged_to_utime) continue;
      truths[k].point_m += Eigen::Map<const Vector3>(t.observation_point_m);
      truths[k].leg_length_m += Eigen::Map<const Vector6>(t.leg_length_m);
      ++counts[k];
    }
  }
  for (std::size_t k = 0; k < dwells.size(); ++k) {
    EXPECT_GT(counts[k], 0) << log_path << ": no rig truth in " << dwells[k].segment;
    truths[k].point_m /= std::max(counts[k], 1);
    truths[k].leg_length_m /= std::max(counts[k], 1);
  }
  return truths;
}

TEST(RigEffectsLive, TheLiveGroupMeasuresWhatEdspSimRigComputes) {
  const std::string config = "config/huang2021-rig-effects.toml";
  const test_support::GroupRun live = test_support::LaunchSimGroup(
      "effects", "signed",
      R"("--motions", "Lz,Rz", "--stops", "3", "--dwell-s", "0.6", "--max-speed-m-s", "0.25",
         "--max-speed-rad-s", "0.4", "--exit-after-hold-s", "0.3")",
      {}, 77, config, test_support::kStallTolerantStaleMs);
  ASSERT_EQ(live.exit_code, 0);

  OfflineRunOptions o;
  o.motions = {"Lz", "Rz"};
  o.paper.stops = 3;
  o.paper.dwell_s = 0.6;
  o.paper.max_speed_m_s = 0.25;
  o.paper.max_speed_rad_s = 0.4;
  o.out_dir = test_support::RunDir(live) + "/offline";
  const std::string config_path = SourcePath("") + config;
  const OfflineRunResult offline = RunOffline(config_path, o);
  ASSERT_EQ(offline.faults, 0);

  const PlatformModel model(LoadConfigFile(config_path));
  const std::vector<DwellError> a = DwellErrorsFromLog(live.log_path, model).dwells;
  const std::vector<DwellError> b = DwellErrorsFromLog(offline.log_path, model).dwells;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 6u);
  const std::vector<DwellTruth> truth_a = DwellTruths(live.log_path, a);
  const std::vector<DwellTruth> truth_b = DwellTruths(offline.log_path, b);
  // Offline, every cycle happens on time; a live cycle this VM stalled long
  // enough is a different history: the rig catches up with a step, its
  // drive overshoots, and a leg's backlash may be left on its other side.
  // So live and offline must agree in what the tracker made of the rig
  // (the measured difference is the true one), and the rig may differ only
  // by that physics: each leg within its backlash of where it stood offline.
  const RigEffects effects = LoadRigEffects(config_path);
  ASSERT_TRUE(effects.backlash.enabled);
  constexpr double kTracked = 3e-6;  // the tracker's noise averaged over a dwell
  constexpr double kThermal = 1e-6;  // a screw's growth from a catch-up's extra travel
  const std::int64_t late =
      test_support::DeadlineMisses(live.log_path, "planner") + test_support::DeadlineMisses(live.log_path, "rig");
  ::testing::Test::RecordProperty("late_cycles", static_cast<int>(late));
  double largest = 0.0, worst = 0.0, leg_moved = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].segment, b[k].segment);
    largest = std::max(largest, b[k].error_norm_m());
    const Vector3 measured = a[k].error_m - b[k].error_m;
    const Vector3 truly = truth_a[k].point_m - truth_b[k].point_m;
    worst = std::max(worst, measured.norm());
    EXPECT_LT((measured - truly).norm(), kTracked)
        << a[k].segment << ": live − offline measured " << measured.transpose() * 1e6 << " µm, truly "
        << truly.transpose() * 1e6 << " µm";
    for (int i = 0; i < 6; ++i) {
      const double moved = std::abs(truth_a[k].leg_length_m(i) - truth_b[k].leg_length_m(i));
      leg_moved = std::max(leg_moved, moved);
      EXPECT_LT(moved, effects.backlash.backlash_m[static_cast<std::size_t>(i)] + kThermal)
          << late << " late planner/rig cycles; " << a[k].segment << ": leg " << i + 1 << " stood " << moved * 1e6
          << " µm from where it stood offline";
    }
  }
  EXPECT_GT(largest, 100e-6);  // the effects are there to be measured
  ::testing::Test::RecordProperty("live_vs_offline_worst_nm", static_cast<int>(worst * 1e9));
  ::testing::Test::RecordProperty("leg_live_vs_offline_worst_nm", static_cast<int>(leg_moved * 1e9));
}

}  // namespace
}  // namespace edsp
