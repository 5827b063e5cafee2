// A node's reporting on its bus (memq://, in process): repeated faults of
// one channel and code are held back and counted, an announced fault never
// is (two members of a group dying in one instant are two faults), and
// EDSP_STATUS goes out at once when the node's state changes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "edsp/channels.h"
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

}  // namespace
}  // namespace edsp
