// LatencyRecorder: exact nearest-rank percentiles against a sort done here,
// and cycles without a sample counted only once the stream has begun.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "edsp/node/latency_recorder.h"

namespace edsp {
namespace {

TEST(LatencyRecorder, PercentilesMatchASortedCopy) {
  LatencyRecorder r;
  std::vector<std::int64_t> values;
  std::mt19937 rng(7);
  for (int k = 0; k < 10001; ++k) {
    values.push_back(std::uniform_int_distribution<std::int64_t>(10, 5000)(rng));
    r.Record(values.back());
  }
  std::sort(values.begin(), values.end());
  const LatencySummary s = r.Summarize();
  EXPECT_EQ(s.samples, 10001);
  EXPECT_EQ(s.p50_us, static_cast<double>(values[5000]));
  EXPECT_EQ(s.p99_us, static_cast<double>(values[9900]));
  EXPECT_EQ(s.p999_us, static_cast<double>(values[9990]));
  EXPECT_EQ(s.max_us, static_cast<double>(values.back()));
  EXPECT_EQ(ToJson(s)["p99_us"].get<double>(), s.p99_us);
}

TEST(LatencyRecorder, CyclesWithoutASampleCountFromTheFirstSample) {
  LatencyRecorder r;
  for (int k = 0; k < 5; ++k) r.EndCycle();  // before the stream: not missed
  r.Record(100);
  r.EndCycle();
  r.EndCycle();  // nothing new
  r.Record(120);
  r.Record(130);  // two in one cycle (a burst)
  r.EndCycle();
  r.EndCycle();  // nothing new
  const LatencySummary s = r.Summarize();
  EXPECT_EQ(s.cycles, 4);
  EXPECT_EQ(s.cycles_without_sample, 2);
  EXPECT_EQ(LatencyRecorder().Summarize().samples, 0);
}

}  // namespace
}  // namespace edsp
