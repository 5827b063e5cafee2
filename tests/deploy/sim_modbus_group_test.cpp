// The sim-modbus group as real processes (label multiprocess, private
// network namespace): the bridge a Modbus TCP master of six CiA 402 drives
// served by edsp-drive-sim, whose axes are the virtual rig's legs through
// its process image. Enabled through the state machine, moved by targets in
// counts, the platform settles point A within 5 µm at every dwell, as the
// sim group does over the shared-memory image.
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/node/node_options.h"
#include "sim_group_harness.h"

namespace edsp {
namespace {

using test_support::DwellEnd;
using test_support::DwellEnds;
using test_support::GroupRun;
using test_support::LaunchSimGroup;
using test_support::SimGroupExtras;

constexpr const char* kDriveSim = R"([[member]]
name = "drive_sim"
command = "edsp-drive-sim"
args = ["--axes", "rig"]
start_delay_ms = 200)";

TEST(SimModbusGroup, OverModbusTcpPointASettlesWithin5umAtEveryDwell) {
  SimGroupExtras extras;
  extras.after_rig = kDriveSim;
  extras.bridge_args = R"(, "--backend", "modbus-tcp")";
  const GroupRun run = LaunchSimGroup("modbus", "signed", test_support::kDefaultPlannerArgs, {}, 77,
                                      test_support::kDefaultConfig, test_support::kStallTolerantStaleMs, extras);
  test_support::ExpectCleanRun(run);
  // The drive simulator ran: the bridge, a Modbus master here, has no other
  // way to the rig's legs.
  EXPECT_NE(ReadTextFile(run.dir + "/launch.err").find("drive_sim        started"), std::string::npos);
  const PlatformModel model(Huang2021Config());
  const std::vector<DwellEnd> ends = DwellEnds(run.log_path, model);
  ASSERT_GE(ends.size(), 5u);  // Lz: 3 stops + home, Rz: 3 stops
  double largest = 0.0;
  for (const DwellEnd& d : ends) {
    EXPECT_LT(d.miss_m, 5e-6) << d.segment;
    largest = std::max(largest, d.miss_m);
  }
  std::printf("sim-modbus: %zu dwells, largest point-A miss %.2f um\n", ends.size(), largest * 1e6);
}

}  // namespace
}  // namespace edsp
