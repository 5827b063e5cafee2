// A node's reporting on its bus (memq://, in process): repeated faults of
// one channel and code are held back and counted, an announced fault never
// is (two members of a group dying in one instant are two faults), and
// EDSP_STATUS goes out at once when the node's state changes; the inputs a
// node watches have their undecodable packets reported and, for the stream
// it follows, their losses counted as its drops.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "edsp/channels.h"
#include "edsp/leg_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/node/node_reporting.h"
#include "memq_bus.h"  // tests/support

namespace edsp {
namespace {

constexpr std::int64_t kReportingNow = 1'000'000'000;

struct ReportingOnABus {
  ReportingOnABus() : bus(test_support::MemqConfig("node_reporting")), reporting(bus, "launcher") {
    bus.Subscribe<fault_t>(std::string(channel::kFault), [this](const fault_t& f) { faults.push_back(f); });
    bus.Subscribe<node_status_t>(std::string(channel::kStatus),
                                 [this](const node_status_t& s) { statuses.push_back(s); });
  }
  void HandleAll() {
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }
  fault_t Died(const std::string& member) const {
    return MakeFault("launcher", "", FaultCode::kProcess, fault_t::SEVERITY_ERROR, "member " + member + ": died",
                     kReportingNow);
  }
  Bus bus;
  NodeReporting reporting;
  std::vector<fault_t> faults;
  std::vector<node_status_t> statuses;
};

TEST(NodeReporting, AFaultRepeatedInOneInstantIsHeldBackButAnAnnouncedOneNever) {
  ReportingOnABus f;
  f.reporting.Fault(f.Died("kinematics"));
  f.reporting.Fault(f.Died("rig"));  // same channel and code, same instant: throttled
  f.HandleAll();
  ASSERT_EQ(f.faults.size(), 1u);
  EXPECT_EQ(f.faults[0].reason, "member kinematics: died");

  f.faults.clear();
  f.reporting.Announce(f.Died("kinematics"));
  f.reporting.Announce(f.Died("rig"));
  f.HandleAll();
  ASSERT_EQ(f.faults.size(), 2u);
  EXPECT_EQ(f.faults[0].reason, "member kinematics: died");
  EXPECT_EQ(f.faults[1].reason, "member rig: died");
}

TEST(NodeReporting, AChangeOfStateIsReportedAtOnceAndOtherwiseOnceASecond) {
  ReportingOnABus f;
  f.reporting.StatusTick(kReportingNow, 0);
  f.reporting.StatusTick(kReportingNow + 100'000, 0);
  f.HandleAll();
  ASSERT_EQ(f.statuses.size(), 1u);
  f.reporting.status().SetState(node_status_t::STATE_FAULT);
  f.reporting.StatusTick(kReportingNow + 200'000, 0);
  f.HandleAll();
  ASSERT_EQ(f.statuses.size(), 2u);
  EXPECT_EQ(f.statuses.back().state, node_status_t::STATE_FAULT);
  EXPECT_EQ(f.statuses.back().node, "launcher");
  f.reporting.StatusTick(kReportingNow + 1'300'000, 0);
  f.HandleAll();
  EXPECT_EQ(f.statuses.size(), 3u);
}

pose_setpoint_t Setpoint(std::int64_t seq) {
  pose_setpoint_t sp{};
  sp.utime = kReportingNow;
  sp.seq = seq;
  sp.trajectory = "Lz";
  return sp;
}

TEST(NodeReporting, WatchedInputsHaveTheirUndecodablePacketsReportedOnceAndTheirLossesCountedAsDrops) {
  ReportingOnABus f;
  f.bus.Subscribe<pose_setpoint_t>(std::string(channel::kSetpoint), [](const pose_setpoint_t&) {});
  f.bus.Subscribe<leg_state_t>(std::string(channel::kLegState), [](const leg_state_t&) {});
  f.reporting.WatchInput(f.bus, channel::kSetpoint, InputLosses::kCountedAsDrops);
  f.reporting.WatchInput(f.bus, channel::kLegState);
  // The followed stream skips seqs 2 and 3; the other input loses 10 to 19.
  for (const std::int64_t seq : {1, 4}) f.bus.Publish(std::string(channel::kSetpoint), Setpoint(seq));
  for (const std::int64_t seq : {9, 20}) {
    leg_state_t legs{};
    legs.seq = seq;
    f.bus.Publish(std::string(channel::kLegState), legs);
  }
  const std::uint8_t noise[3] = {1, 2, 3};
  f.bus.lcm().Publish(std::string(channel::kLegState), noise, 3);
  f.HandleAll();
  f.reporting.StatusTick(kReportingNow, 0);
  f.HandleAll();
  ASSERT_EQ(f.faults.size(), 1u);
  EXPECT_EQ(f.faults[0].channel, channel::kLegState);
  EXPECT_NE(f.faults[0].reason.find("1 undecodable packets"), std::string::npos) << f.faults[0].reason;
  ASSERT_EQ(f.statuses.size(), 1u);
  EXPECT_EQ(f.statuses[0].drops, 2) << "the followed stream's losses only";
  // Nothing new: nothing said again.
  f.reporting.StatusTick(kReportingNow + 1000, 0);
  f.HandleAll();
  EXPECT_EQ(f.faults.size(), 1u);
}

}  // namespace
}  // namespace edsp
