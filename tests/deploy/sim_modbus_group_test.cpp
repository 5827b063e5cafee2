// The sim-modbus group as real processes (label multiprocess, private
// network namespace): the bridge a Modbus TCP master of six CiA 402 drives
// served by edsp-drive-sim, whose axes are the virtual rig's legs through
// its process image. Enabled through the state machine, moved by targets in
// counts, the platform settles point A within 5 µm at every dwell, as the
// sim group does over the shared-memory image.
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

using test_support::DwellEnd;
using test_support::DwellEnds;
using test_support::GroupRun;
using test_support::LaunchSimGroup;
using test_support::SimGroupExtras;

// For a test of accuracy, not of holding (as kStallTolerantStaleMs): on
// this shared 2-core VM a drive simulator descheduled past the shipped
// 5 ms response timeout (a busy fresh-clone CI run) or a bridge silent past
// the drives' 20 ms fieldbus timeout is a correct hold, not what this
// measures. Both tolerate the stale limit's 250 ms here.
constexpr const char* kDriveSim = R"([[member]]
name = "drive_sim"
command = "edsp-drive-sim"
args = ["--axes", "rig", "--fieldbus-timeout-ms", "250"]
start_delay_ms = 200)";

// The shipped config with the Modbus response timeout at the stall-tolerant limit.
std::string StallTolerantConfig(const std::string& dir) {
  std::string text = ReadTextFile(std::string(EDSP_SOURCE_DIR) + "/" + test_support::kDefaultConfig);
  const std::string key = "counts_per_m = 104857600";
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return "";
  text.insert(at + key.size(),
              "\nresponse_timeout_ms = " + std::to_string(test_support::kStallTolerantStaleMs));
  std::system(("mkdir -p " + dir).c_str());
  std::ofstream(dir + "/modbus.toml") << text;
  return dir + "/modbus.toml";
}

TEST(SimModbusGroup, OverModbusTcpPointASettlesWithin5umAtEveryDwell) {
  SimGroupExtras extras;
  extras.after_rig = kDriveSim;
  extras.bridge_args = R"(, "--backend", "modbus-tcp")";
  const std::string config = StallTolerantConfig(test_support::SimGroupDir("modbus"));
  ASSERT_FALSE(config.empty()) << "config/huang2021.toml declares no [drives] counts_per_m";
  const GroupRun run = LaunchSimGroup("modbus", "signed", test_support::kDefaultPlannerArgs, {}, 77, config,
                                      test_support::kStallTolerantStaleMs, extras);
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
