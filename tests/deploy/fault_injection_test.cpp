// Faults injected into a running sim group (label multiprocess, private
// network namespace): what a rig meets from outside while it moves.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/fault_t.hpp"
#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/node/fault.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/lcm_transport.h"
#include "group_watch.h"
#include "late_cycles.h"
#include "sim_group_harness.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

// Garbage, and packets that start like the real type (right fingerprint)
// but are truncated or carry a corrupt string length, on every channel the
// nodes read, for `seconds`. Returns how many were sent.
long Flood(double seconds) {
  LcmTransport lcm(kDefaultLcmUrl);
  std::mt19937 random(7);
  pose_setpoint_t sp{};
  sp.session_id = 77;
  sp.trajectory = "flood";
  std::vector<std::uint8_t> real(static_cast<std::size_t>(sp.getEncodedSize()));
  sp.encode(real.data(), 0, static_cast<int>(real.size()));
  std::vector<std::uint8_t> corrupt = real;
  std::fill(corrupt.begin() + 176, corrupt.begin() + 180, std::uint8_t{0xFF});  // trajectory length -1
  const char* channels[] = {"EDSP_SETPOINT", "EDSP_LEG_COMMAND", "EDSP_LEG_STATE", "EDSP_ARM", "EDSP_PR_MODE"};
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  long sent = 0;
  while (std::chrono::steady_clock::now() < until) {
    for (const char* channel : channels) {
      std::vector<std::uint8_t> bytes;
      switch (random() % 3) {
        case 0:
          bytes.resize(random() % 300);
          for (auto& b : bytes) b = static_cast<std::uint8_t>(random());
          break;
        case 1: bytes.assign(real.begin(), real.begin() + static_cast<long>(random() % real.size())); break;
        default: bytes = corrupt; break;
      }
      lcm.Publish(channel, bytes.data(), static_cast<std::uint32_t>(bytes.size()));
      ++sent;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500));  // ~10 000 packets a second
  }
  return sent;
}

// The flood's program (kDefaultPlannerArgs: Lz and Rz, three stops and
// home each, dwells of 0.6 s): dwell ends followed by another segment.
constexpr std::size_t kFloodProgramDwellEnds = 7;
constexpr double kDwellS = 0.6;

// The longest stretch (s) of the log without a setpoint that decodes as
// one: what a logger that lost packets at its socket leaves out.
double LongestSetpointSilenceS(const std::string& log_path) {
  LogReader reader(log_path);
  LogEvent event;
  std::int64_t previous = 0, longest = 0;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_SETPOINT" || !test_support::DecodesAsItsChannelsType(event.channel, event.data)) {
      continue;
    }
    if (previous != 0) longest = std::max(longest, event.timestamp_utime - previous);
    previous = event.timestamp_utime;
  }
  return static_cast<double>(longest) * 1e-6;
}

TEST(FaultInjection, AFloodOfForeignPacketsOnEveryInputMovesNothingAndStopsNoNode) {
  long sent = 0;
  const GroupRun run = LaunchSimGroup(
      "flood", "signed", test_support::kDefaultPlannerArgs,
      [&](const std::string&) {
        {
          // Once the nodes that decode commands publish, not after a sleep:
          // a sanitized node on a busy two-core machine starts several
          // times slower. The watch is gone before the flood, which it
          // would otherwise take whole.
          test_support::GroupWatch watch(test_support::kGroupLcmUrl, "EDSP_LEG_COMMAND|EDSP_LEG_STATE");
          if (!watch.WaitForMessage("EDSP_LEG_COMMAND", 0, std::chrono::seconds(60)) ||
              !watch.WaitForMessage("EDSP_LEG_STATE", 0, std::chrono::seconds(60))) {
            return;  // fails below: nothing sent
          }
        }
        sent = Flood(4.0);
      },
      77, test_support::kDefaultConfig, test_support::kStallTolerantStaleMs);
  ASSERT_EQ(run.exit_code, 0) << "see " << test_support::RunDir(run) << "/launch.err";
  std::printf("foreign packets sent: %ld\n", sent);
  ::testing::Test::RecordProperty("foreign_packets", static_cast<int>(sent));
  EXPECT_GT(sent, 10000);
  // No node died: the launcher restarted nobody.
  std::ifstream err(test_support::RunDir(run) + "/launch.err");
  std::stringstream text;
  text << err.rdbuf();
  EXPECT_EQ(text.str().find("restart"), std::string::npos) << text.str();
  // Refused and said so: the nodes reading commands reported undecodable packets.
  int kinematics = 0, bridge = 0, latches = 0;
  std::int64_t first_latch_utime = 0;
  LogReader reader(run.log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_FAULT") continue;
    fault_t f;
    if (f.decode(event.data.data(), 0, static_cast<int>(event.data.size())) < 0) continue;
    if (f.node == "actuator_bridge" && f.code == static_cast<std::int32_t>(FaultCode::kLatched)) {
      if (latches++ == 0) first_latch_utime = f.utime;
    }
    if (f.code != static_cast<std::int32_t>(FaultCode::kUndecodable)) continue;
    if (f.node == "kinematics") ++kinematics;
    if (f.node == "actuator_bridge") ++bridge;
  }
  EXPECT_GT(kinematics, 0);
  EXPECT_GT(bridge, 0);
  if (latches > 0) {
    // The bridge held, which moves nothing. Only the machine may have made
    // it hold, never the flood: before the latch, a loop feeding the bridge
    // (or the bridge) ran late by half the stale limit or more, or the rig
    // emulator's drives fell silent by half their timeout or more
    // (late_cycles.h). A machine that cannot run the group in real time (a
    // sanitized group at half speed) cannot then show the dwells.
    const test_support::LatenessAroundTheBridge late =
        test_support::LatenessAroundTheBridgeWithin(run.log_path, 0, first_latch_utime);
    std::printf("the bridge latched; %s\n", late.Describe().c_str());
    EXPECT_TRUE(late.ExplainsALatch(test_support::kStallTolerantStaleMs * 1000))
        << "the bridge latched under the flood with no stall to explain it: " << late.Describe();
    return;
  }
  // Moved exactly as without the flood: every dwell the log holds within
  // 5 µm. A sanitized logger taking the flood on a busy machine can lose
  // seconds of every channel at its socket (counted: seq gaps); a dwell
  // inside such a stretch cannot be checked, and only such a loss may hide
  // one.
  const std::vector<DwellEnd> ends = DwellEnds(run.log_path, PlatformModel(Huang2021Config()));
  for (const DwellEnd& d : ends) EXPECT_LT(d.miss_m, 5e-6) << d.segment;
  if (ends.size() < kFloodProgramDwellEnds) {
    const double silence_s = LongestSetpointSilenceS(run.log_path);
    std::printf("%zu of the program's %zu dwell ends in the log; it holds no setpoint for %.2f s at most\n",
                ends.size(), kFloodProgramDwellEnds, silence_s);
    EXPECT_GT(silence_s, kDwellS) << "dwells missing from the log with no loss of the logger's to hide them";
    EXPECT_GE(ends.size(), 2u) << "too little of the run logged to check that the flood moved nothing";
  }
}

}  // namespace
}  // namespace edsp
