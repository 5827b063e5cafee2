#include "edsp/node/latency_recorder.h"

#include <algorithm>

namespace edsp {

namespace {

// Nearest-rank percentile of sorted values.
double Percentile(const std::vector<std::int64_t>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const auto rank = static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1) + 0.5);
  return static_cast<double>(sorted[std::min(rank, sorted.size() - 1)]);
}

}  // namespace

LatencySummary LatencyRecorder::Summarize() const {
  std::vector<std::int64_t> sorted = us_;
  std::sort(sorted.begin(), sorted.end());
  LatencySummary s;
  s.samples = static_cast<std::int64_t>(sorted.size());
  s.p50_us = Percentile(sorted, 0.50);
  s.p99_us = Percentile(sorted, 0.99);
  s.p999_us = Percentile(sorted, 0.999);
  s.max_us = sorted.empty() ? 0.0 : static_cast<double>(sorted.back());
  s.cycles = cycles_;
  s.cycles_without_sample = empty_cycles_;
  return s;
}

nlohmann::json ToJson(const LatencySummary& s) {
  return {{"samples", s.samples},
          {"p50_us", s.p50_us},
          {"p99_us", s.p99_us},
          {"p999_us", s.p999_us},
          {"max_us", s.max_us},
          {"cycles", s.cycles},
          {"cycles_without_sample", s.cycles_without_sample}};
}

}  // namespace edsp
