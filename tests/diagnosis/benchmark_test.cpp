// The benchmark's scores against the scenarios' own figures: what a perfect
// model would reach is the held-out gap down to the tracker's noise floor,
// the gap is what lies above the noise the generator added, and the medians
// are taken over the same scenarios.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/gap/benchmark.h"

namespace edsp::gap {
namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The kinds the benchmark scores by, under the names its JSON and the blind
// rig's draws use: each kind has its name, each name reads back as its kind,
// and nothing else reads.
TEST(ScenarioKinds, EachNameReadsBackAsItsKindAndNoOtherNameReads) {
  const std::vector<std::pair<ScenarioKind, std::string>> contract = {
      {ScenarioKind::kNone, "none"},
      {ScenarioKind::kSingle, "single"},
      {ScenarioKind::kPair, "pair"},
      {ScenarioKind::kOutOfVocabulary, "out_of_vocabulary"},
      {ScenarioKind::kWholeRig, "whole_rig"}};
  for (const auto& [kind, name] : contract) {
    EXPECT_EQ(ScenarioKindName(kind), name);
    EXPECT_EQ(ParseScenarioKind(name), kind) << name;
  }
  for (const char* foreign : {"", "whole", "None", "pairs"}) EXPECT_FALSE(ParseScenarioKind(foreign)) << foreign;
  EXPECT_EQ(KindOfEffects(0), ScenarioKind::kNone);
  EXPECT_EQ(KindOfEffects(1), ScenarioKind::kSingle);
  EXPECT_EQ(KindOfEffects(2), ScenarioKind::kPair);
  EXPECT_EQ(KindOfEffects(3), ScenarioKind::kPair);
}

TEST(Benchmark, TheGapIsTheDepartureAboveTheTrackersNoise) {
  const double floor = 10e-6, before = 50e-6;
  const double gap = std::sqrt(before * before - floor * floor);
  // The RMS's shrink stops at the floor: 1 − 10/50 however good the model.
  EXPECT_DOUBLE_EQ(Shrink(before, floor), 0.8);
  EXPECT_DOUBLE_EQ(Shrink(0.0, floor), 0.0);
  EXPECT_DOUBLE_EQ(GapShrink(before, floor, floor), 1.0);     // only the noise left
  EXPECT_DOUBLE_EQ(GapShrink(before, 6e-6, floor), 1.0);      // under it by the noise's own sampling
  EXPECT_NEAR(GapShrink(before, before, floor), 0.0, 1e-12);  // the gap as it was
  EXPECT_NEAR(GapShrink(before, std::hypot(floor, gap / 2), floor), 0.5, 1e-12);
  EXPECT_LT(GapShrink(before, 60e-6, floor), 0.0);      // a model that makes it worse says so
  EXPECT_DOUBLE_EQ(GapShrink(9e-6, 5e-6, floor), 0.0);  // no gap above the noise: nothing to shrink
  // In words: a 0 with no gap to close is not a model that failed.
  EXPECT_EQ(GapShrinkText(9e-6, floor, 0.0), "no gap above it");
  EXPECT_EQ(GapShrinkText(before, floor, 0.0), "0.0% of the gap above it closed");
  EXPECT_EQ(GapShrinkText(before, floor, 0.964), "96.4% of the gap above it closed");
}

// Blind seed 11's first three scenarios: effect-free, then two single
// effects, both found. The noise the gap is scored against is the one the
// generator added, which the data confirm: the diagnosis's own floor, from
// sample-to-sample differences at rest, lands on √3·σ.
TEST(Benchmark, TheShrinkIsScoredAgainstTheTrackersNoise) {
  BenchmarkOptions o;
  o.generator = Generator::kBlind;
  o.scenarios = 3;
  o.seed = 11;
  o.progress = false;
  const nlohmann::json j = ToJson(RunBenchmark(o));
  std::vector<double> attainable, shrink, gaps;
  for (const nlohmann::json& s : j.at("results")) {
    const double before = s.at("holdout_before_rms_m").get<double>(), after = s.at("holdout_after_rms_m").get<double>();
    const double floor = s.at("noise_floor_rms_m").get<double>(), sigma = s.at("noise_sigma_m").get<double>();
    ASSERT_GT(before, 0.0);
    EXPECT_NEAR(s.at("attainable_shrink").get<double>(), std::max(0.0, 1.0 - floor / before), 1e-12);
    // A model can take the gap below the floor only by the floor estimate's error.
    EXPECT_LT(s.at("shrink").get<double>(), s.at("attainable_shrink").get<double>() + 0.03) << s.dump();
    ASSERT_GT(sigma, 0.0) << s.dump();
    EXPECT_NE(sigma, o.tracker_noise_m) << "the rig's noise, not the blind rig's draw";
    EXPECT_NEAR(floor, std::sqrt(3.0) * sigma, 0.1 * std::sqrt(3.0) * sigma) << s.dump();
    EXPECT_DOUBLE_EQ(s.at("gap_shrink").get<double>(), GapShrink(before, after, std::sqrt(3.0) * sigma));
    if (s.at("kind") == "none") continue;
    attainable.push_back(s.at("attainable_shrink").get<double>());
    shrink.push_back(s.at("shrink").get<double>());
    gaps.push_back(s.at("gap_shrink").get<double>());
  }
  ASSERT_EQ(attainable.size(), 2u);
  EXPECT_DOUBLE_EQ(j.at("median_attainable_shrink").get<double>(), Median(attainable));
  EXPECT_DOUBLE_EQ(j.at("median_shrink").get<double>(), Median(shrink));
  EXPECT_DOUBLE_EQ(j.at("median_gap_shrink").get<double>(), Median(gaps));
  // A found effect takes the residual to the floor: within a few points of
  // what is attainable, and most of the gap above the noise closed.
  EXPECT_GT(j.at("median_shrink").get<double>(), j.at("median_attainable_shrink").get<double>() - 0.05) << j.dump(1);
  EXPECT_GT(j.at("median_gap_shrink").get<double>(), 0.85) << j.dump(1);
}

// --encoders without: every scenario's CSV lacks the encoder columns,
// whatever was drawn, and the JSON says which choice it ran with.
TEST(Benchmark, EncodersCanBeLeftOutOfEveryBlindScenario) {
  BenchmarkOptions o;
  o.generator = Generator::kBlind;
  o.encoders = EncoderColumns::kWithout;
  o.scenarios = 1;
  o.seed = 5;
  o.progress = false;
  const nlohmann::json j = ToJson(RunBenchmark(o));
  EXPECT_EQ(j.at("encoders"), "without");
  for (const nlohmann::json& s : j.at("results")) {
    EXPECT_NE(s.at("description").get<std::string>().find("without encoders"), std::string::npos) << s.dump();
  }
}

// The rig's tracker always has encoders: forcing them there is an error
// that names the choice.
TEST(Benchmark, AnEncoderChoiceTheGeneratorCannotHonourIsAnError) {
  BenchmarkOptions o;
  o.progress = false;
  for (EncoderColumns forced : {EncoderColumns::kWith, EncoderColumns::kWithout}) {
    o.encoders = forced;
    try {
      RunBenchmark(o);
      ADD_FAILURE() << "the rig generator accepted --encoders " << EncoderColumnsName(forced);
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + EncoderColumnsName(forced) + "'"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace edsp::gap
