// The sim-modbus and sim-cia402 groups as real processes (label
// multiprocess, private network namespace): the bridge a CiA 402 master of
// six drives served by edsp-drive-sim, over Modbus TCP or the shared-memory
// CSP image, the drives' axes the virtual rig's legs through its process
// image. Enabled through the state machine, moved by targets in counts, the
// platform settles point A within 5 µm at every dwell, as the sim group
// does over the rig's own image.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/node/node_options.h"
#include "sim_group_harness.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

// The group `group` run as `name`: point A within 5 µm at every dwell.
// For a test of accuracy, not of holding (as kStallTolerantStaleMs): on
// a shared machine a drive simulator descheduled past the shipped 5 ms
// response timeout, a bridge silent past the drives' 20 ms fieldbus
// timeout, or drives 8 ms behind a rig moving the legs at 0.25 m/s (past
// the 1.9 mm following window) is a correct fault and hold, not what this
// measures. All tolerate the stale limit's 250 ms here.
void ExpectEveryDwellWithin5um(const std::string& group, const std::string& name) {
  std::string config;
  const SimGroupExtras extras =
      test_support::OverModbus(test_support::SimGroupDir(name), test_support::kStallTolerantStaleMs, &config, group);
  ASSERT_FALSE(config.empty()) << "config/huang2021.toml declares no [drives] counts_per_m";
  const GroupRun run = LaunchSimGroup(name, "signed", test_support::kDefaultPlannerArgs, {}, 77, config,
                                      test_support::kStallTolerantStaleMs, extras);
  test_support::ExpectCleanRun(run);
  // The drive simulator ran: the bridge, a CiA 402 master here, has no other
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
  std::printf("%s: %zu dwells, largest point-A miss %.2f um\n", group.c_str(), ends.size(), largest * 1e6);
}

TEST(SimModbusGroup, OverModbusTcpPointASettlesWithin5umAtEveryDwell) {
  ExpectEveryDwellWithin5um("sim-modbus", "modbus");
}

// The same drives, the image in shared memory: what an EtherCAT master
// process would serve (docs/drives.md).
TEST(SimCia402Group, OverTheSharedMemoryCspImagePointASettlesWithin5umAtEveryDwell) {
  ExpectEveryDwellWithin5um("sim-cia402", "cia402");
}

}  // namespace
}  // namespace edsp
