// EDSP_STATUS: once a second, and at once when the node's state changes, so
// that a hold shorter than a second is seen by whoever watches the status.
#include <gtest/gtest.h>

#include "edsp/node/runtime.h"

namespace edsp {
namespace {

// Runs a 1 kHz loop from `from` to `to` (µs), setting `state` each cycle as
// the nodes do; returns the times at which a report was due, and publishes it.
std::vector<std::int64_t> Loop(NodeStatus& status, std::int64_t from, std::int64_t to, std::int8_t state) {
  std::vector<std::int64_t> due;
  for (std::int64_t t = from; t < to; t += 1000) {
    status.SetState(state);
    if (status.Due(t)) {
      due.push_back(t);
      EXPECT_EQ(status.Report(t, 0).state, state);
    }
  }
  return due;
}

TEST(NodeStatus, OnceASecondWhileTheStateHolds) {
  NodeStatus status("test");
  status.SetState(node_status_t::STATE_RUNNING);
  const auto due = Loop(status, 1'000'000, 4'000'000, node_status_t::STATE_RUNNING);
  EXPECT_EQ(due, (std::vector<std::int64_t>{1'000'000, 2'000'000, 3'000'000}));
}

TEST(NodeStatus, AChangeOfStateIsReportedAtOnceAndTheSecondlyRhythmKept) {
  NodeStatus status("test");
  Loop(status, 1'000'000, 1'200'000, node_status_t::STATE_RUNNING);  // reported at 1.0 s
  // A 300 ms hold between two secondly reports.
  const auto hold = Loop(status, 1'200'000, 1'500'000, node_status_t::STATE_HOLDING);
  EXPECT_EQ(hold, std::vector<std::int64_t>{1'200'000});
  const auto back = Loop(status, 1'500'000, 2'500'000, node_status_t::STATE_RUNNING);
  EXPECT_EQ(back, (std::vector<std::int64_t>{1'500'000, 2'000'000}));
}

// A state that flips every cycle cannot flood the channel: at most one
// report per 10 ms, and the last state is still reported.
TEST(NodeStatus, AFlappingStateIsReportedAtMostEvery10ms) {
  NodeStatus status("test");
  int reports = 0;
  for (std::int64_t t = 1'000'000; t < 1'100'000; t += 1000) {
    status.SetState((t / 1000) % 2 ? node_status_t::STATE_HOLDING : node_status_t::STATE_RUNNING);
    if (status.Due(t)) ++reports, status.Report(t, 0);
  }
  EXPECT_LE(reports, 11);
  EXPECT_GE(reports, 9);
}

}  // namespace
}  // namespace edsp
