// Six simulated drives behind edsp's Modbus TCP server, driven over
// loopback by the master as a backend will: one read/write request a
// cycle, the drives enabled through CiA 402 by their statuswords, a drive's
// fault seen with its code and cleared by a fault reset, and every failure
// of the wire (server gone, nobody listening, a restarted server) reported
// with the endpoint and the reason.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include "edsp/drives/csp_master.h"
#include "edsp/drives/modbus_drive_master.h"
#include "edsp/drives/modbus_drive_server.h"
#include "served_drives.h"

namespace edsp::cia402 {
namespace {

using test_support::ServedDrives;

// One master cycle towards `wanted` (empty: hold); false with *error.
struct Master {
  ModbusDriveMaster wire;
  CspCommands commands{};
  CspFeedbacks feedback{};
  explicit Master(int port) : wire("127.0.0.1", port, 0.5) {}
  bool Cycle(std::optional<std::int32_t> wanted, std::string* error) {
    for (std::size_t d = 0; d < commands.size(); ++d) {
      commands[d] = NextCspCommand(feedback[d], commands[d].controlword, wanted);
    }
    const bool ok = wire.Exchange(commands, &feedback, error);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return ok;
  }
  bool AllIn(State state) const {
    for (const CspFeedback& f : feedback) {
      if (StateOfStatusword(f.statusword) != state) return false;
    }
    return true;
  }
};

TEST(ModbusDrives, SixDrivesEnabledOverTheWireFollowTheirTargets) {
  ServedDrives drives;
  Master master(drives.port());
  std::string error;
  ASSERT_TRUE(master.wire.Connect(&error)) << error;
  int cycles = 0;
  for (; cycles < 200 && !master.AllIn(State::kOperationEnabled); ++cycles)
    ASSERT_TRUE(master.Cycle(0, &error)) << error;
  EXPECT_TRUE(master.AllIn(State::kOperationEnabled)) << "after " << cycles << " cycles";
  for (int k = 0; k < 200; ++k) ASSERT_TRUE(master.Cycle(250000, &error)) << error;
  for (const CspFeedback& f : master.feedback) {
    EXPECT_EQ(f.position_actual, 250000);
    EXPECT_EQ(f.error_code, 0);
  }
  EXPECT_GE(drives.server().requests(), 200);
}

TEST(ModbusDrives, ADrivesFaultArrivesWithItsCodeAndAFaultResetClearsIt) {
  ServedDrives drives;
  Master master(drives.port());
  std::string error;
  ASSERT_TRUE(master.wire.Connect(&error)) << error;
  for (int k = 0; k < 200 && !master.AllIn(State::kOperationEnabled); ++k) ASSERT_TRUE(master.Cycle(0, &error));
  drives.server().InjectFault(2, 0x7500);
  int cycles = 0;
  for (; cycles < 200 && StateOfStatusword(master.feedback[2].statusword) != State::kFault; ++cycles) {
    ASSERT_TRUE(master.Cycle(0, &error));
  }
  EXPECT_EQ(StateOfStatusword(master.feedback[2].statusword), State::kFault);
  EXPECT_EQ(master.feedback[2].error_code, 0x7500);
  EXPECT_EQ(StateOfStatusword(master.feedback[1].statusword), State::kOperationEnabled) << "the others run on";
  for (int k = 0; k < 200 && !master.AllIn(State::kOperationEnabled); ++k) ASSERT_TRUE(master.Cycle(0, &error));
  EXPECT_TRUE(master.AllIn(State::kOperationEnabled)) << "re-enabled after the fault reset";
  EXPECT_EQ(master.feedback[2].error_code, 0);
}

TEST(ModbusDrives, NobodyListeningIsRefusedWithTheEndpoint) {
  int port = 0;
  {
    ServedDrives gone;
    port = gone.port();
  }  // a port that was just free, now closed
  ModbusDriveMaster master("127.0.0.1", port, 0.2);
  std::string error;
  EXPECT_FALSE(master.Connect(&error));
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_NE(error.find("refused"), std::string::npos) << error;
}

TEST(ModbusDrives, AServerThatGoesAwayFailsTheCycleAndARestartedOneIsReachedAgain) {
  auto drives = std::make_unique<ServedDrives>();
  const int port = drives->port();
  Master master(port);
  std::string error;
  ASSERT_TRUE(master.wire.Connect(&error)) << error;
  ASSERT_TRUE(master.Cycle(0, &error)) << error;
  drives.reset();  // the drive simulator exits
  EXPECT_FALSE(master.Cycle(0, &error));
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_FALSE(master.wire.connected()) << "a failed cycle drops the connection";
  drives = std::make_unique<ServedDrives>(port);  // back on the same port
  ASSERT_TRUE(master.wire.Connect(&error)) << error;
  EXPECT_TRUE(master.Cycle(0, &error)) << error;
}

}  // namespace
}  // namespace edsp::cia402
