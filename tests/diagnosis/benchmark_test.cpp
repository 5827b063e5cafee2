// The benchmark's scores against the scenarios' own figures: what a perfect
// model would reach is the held-out gap down to the tracker's noise floor,
// and the median shrink is measured on the same scenarios.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/benchmark.h"

namespace edsp::gap {
namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

TEST(Benchmark, TheAttainableShrinkIsTheGapDownToTheNoiseFloor) {
  BenchmarkOptions o;
  o.generator = "blind";
  o.scenarios = 3;  // effect-free, then two single effects
  o.seed = 11;
  o.progress = false;
  const nlohmann::json j = ToJson(RunBenchmark(o));
  std::vector<double> attainable, shrink;
  for (const nlohmann::json& s : j.at("results")) {
    const double before = s.at("holdout_before_rms_m").get<double>(), floor = s.at("noise_floor_rms_m").get<double>();
    ASSERT_GT(before, 0.0);
    EXPECT_NEAR(s.at("attainable_shrink").get<double>(), std::max(0.0, 1.0 - floor / before), 1e-12);
    // A model can take the gap below the floor only by the floor estimate's error.
    EXPECT_LT(s.at("shrink").get<double>(), s.at("attainable_shrink").get<double>() + 0.03) << s.dump();
    if (s.at("kind") == "none") continue;
    attainable.push_back(s.at("attainable_shrink").get<double>());
    shrink.push_back(s.at("shrink").get<double>());
  }
  ASSERT_EQ(attainable.size(), 2u);
  EXPECT_DOUBLE_EQ(j.at("median_attainable_shrink").get<double>(), Median(attainable));
  EXPECT_DOUBLE_EQ(j.at("median_shrink").get<double>(), Median(shrink));
  // A found effect takes the gap to the floor: within a few points of what is attainable.
  EXPECT_GT(j.at("median_shrink").get<double>(), j.at("median_attainable_shrink").get<double>() - 0.05) << j.dump(1);
}

// --encoders without: every scenario's CSV lacks the encoder columns,
// whatever was drawn, and the JSON says which choice it ran with.
TEST(Benchmark, EncodersCanBeLeftOutOfEveryBlindScenario) {
  BenchmarkOptions o;
  o.generator = "blind";
  o.encoders = "without";
  o.scenarios = 1;
  o.seed = 5;
  o.progress = false;
  const nlohmann::json j = ToJson(RunBenchmark(o));
  EXPECT_EQ(j.at("encoders"), "without");
  for (const nlohmann::json& s : j.at("results")) {
    EXPECT_NE(s.at("description").get<std::string>().find("without encoders"), std::string::npos) << s.dump();
  }
}

// The rig's tracker always has encoders: forcing them there, or a word
// that is not a choice, is an error that names the value.
TEST(Benchmark, AnEncoderChoiceTheGeneratorCannotHonourIsAnError) {
  const auto expect_refused = [](const BenchmarkOptions& o) {
    try {
      RunBenchmark(o);
      ADD_FAILURE() << o.generator << " generator accepted --encoders " << o.encoders;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + o.encoders + "'"), std::string::npos) << e.what();
    }
  };
  BenchmarkOptions o;
  o.progress = false;
  o.encoders = "without";
  expect_refused(o);
  o.generator = "blind";
  o.encoders = "some";
  expect_refused(o);
}

}  // namespace
}  // namespace edsp::gap
