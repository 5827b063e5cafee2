#pragma once
// End-to-end latencies of a stream (e.g. setpoint → drive setpoint), kept
// whole so percentiles are exact, and the 1 kHz cycles in which the stream
// delivered nothing new. Summarised as JSON for benchmarks (--latency-report).

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace edsp {

struct LatencySummary {
  std::int64_t samples = 0;
  double p50_us = 0.0, p99_us = 0.0, p999_us = 0.0, max_us = 0.0;
  std::int64_t cycles = 0;                 // cycles since the first sample
  std::int64_t cycles_without_sample = 0;  // of those, cycles nothing new arrived in
};

class LatencyRecorder {
 public:
  explicit LatencyRecorder(std::size_t reserve = 1 << 17) { us_.reserve(reserve); }
  void Record(std::int64_t latency_us) {
    us_.push_back(latency_us);
    fresh_ = true;
  }
  // Call once per cycle: counts a cycle without a sample once the stream began.
  void EndCycle() {
    if (us_.empty()) return;
    ++cycles_;
    if (!fresh_) ++empty_cycles_;
    fresh_ = false;
  }
  LatencySummary Summarize() const;

 private:
  std::vector<std::int64_t> us_;
  bool fresh_ = false;
  std::int64_t cycles_ = 0, empty_cycles_ = 0;
};

// {"samples", "p50_us", "p99_us", "p999_us", "max_us", "cycles", "cycles_without_sample"}
nlohmann::json ToJson(const LatencySummary& s);

}  // namespace edsp
