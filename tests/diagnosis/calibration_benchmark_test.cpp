// The whole-rig calibration benchmark on one rig and one design: what it
// reports applied is what the saved model applies (the diagnosis's own
// calibration set), and its verdict follows from its own figures.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/gap/calibration_benchmark.h"

namespace edsp::gap {
namespace {

TEST(CalibrationBenchmark, ReportsWhatItAppliedAndScoresItsOwnFigures) {
  CalibrationBenchmarkOptions o;
  o.rigs = 1;
  o.seed = 17;
  o.designs = {{"six", {"Lz", "Lx", "Rz", "Ry", "M1", "M2"}}};
  o.held_out = {"M3"};
  o.progress = false;
  const CalibrationBenchmarkResult r = RunCalibrationBenchmark(o);
  ASSERT_EQ(r.rigs.size(), 1u);
  ASSERT_EQ(r.rigs[0].designs.size(), 1u);
  const DesignScore& s = r.rigs[0].designs[0];
  ASSERT_TRUE(s.error.empty()) << s.error;
  // A whole rig has every static effect: a calibration applies several.
  EXPECT_GE(s.applied.size(), 2u);
  for (const std::string& name : s.applied) EXPECT_FALSE(name.empty());
  EXPECT_LT(s.after_rms_m, s.before_rms_m);
  const bool met = (s.after_rms_m <= kCalibrationTargetFloorRatio * r.rigs[0].noise_floor_m ||
                    s.after_rms_m <= (1.0 - kCalibrationTargetShrink) * s.before_rms_m) &&
                   s.after_max_m <= s.before_max_m;
  EXPECT_EQ(s.met, met);
  const nlohmann::json j = ToJson(r);
  EXPECT_EQ(j["rigs"][0]["six"]["applied"].size(), s.applied.size());
  EXPECT_EQ(j["designs"][0]["met"].get<int>(), met ? 1 : 0);
}

// On the blind rig both designs run: the designed motions as edsp's planner
// plans them, played by the blind rig's controller; each is scored.
TEST(CalibrationBenchmark, OnTheBlindRigBothDesignsAreScored) {
  CalibrationBenchmarkOptions o;
  o.rigs = 1;
  o.seed = 17;
  o.generator = Generator::kBlind;
  o.held_out = {"M3"};
  o.progress = false;
  const CalibrationBenchmarkResult r = RunCalibrationBenchmark(o);
  ASSERT_EQ(r.rigs.size(), 1u);
  ASSERT_EQ(r.rigs[0].designs.size(), 2u);
  for (const DesignScore& s : r.rigs[0].designs) {
    ASSERT_TRUE(s.error.empty()) << s.design << ": " << s.error;
    EXPECT_GE(s.applied.size(), 2u) << s.design;
    EXPECT_GT(s.fit_duration_s, 10.0) << s.design;
    EXPECT_LT(s.after_rms_m, 0.5 * s.before_rms_m) << s.design;
  }
  EXPECT_EQ(ToJson(r)["generator"], "blind");
}

}  // namespace
}  // namespace edsp::gap
