// The shared-memory CSP image between a master and six simulated drives
// (edsp-drive-sim --serve shm's server, on a thread): drives that stop
// latching are reported silent once the response timeout has passed, by
// the segment's name, and a dead master's last RxPDOs left in the ring are
// never taken as a command by drives that start after it.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/drives/cia402.h"
#include "edsp/drives/csp_shm_image.h"
#include "edsp/drives/csp_shm_master.h"
#include "edsp/drives/csp_shm_server.h"

namespace edsp::cia402 {
namespace {

std::string Prefix(const char* name) { return fmt::format("edsp.test.{}.{}", ::getpid(), name); }

// The drives' server on a thread while it lives.
class Served {
 public:
  explicit Served(const std::string& prefix) : server_(Options(prefix)) {
    thread_ = std::thread([this] { server_.Run([this] { return stop_.load(); }); });
  }
  ~Served() {
    stop_ = true;
    thread_.join();
  }
  CspShmServer& server() { return server_; }

 private:
  static ShmDriveServerOptions Options(const std::string& prefix) {
    ShmDriveServerOptions o;
    o.prefix = prefix;
    o.drive.fieldbus_timeout_s = 2.0;
    return o;
  }
  CspShmServer server_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

CspCommands AllShutdown() {
  CspCommands c{};
  for (CspCommand& d : c) {
    d.controlword = ControlwordFor(Command::kShutdown);
    d.mode_of_operation = kModeCyclicSynchronousPosition;
  }
  return c;
}

TEST(CspShmLink, DrivesThatStopLatchingAreSilentAfterTheResponseTimeoutNamed) {
  const std::string prefix = Prefix("silent");
  Served drives(prefix);
  constexpr double kTimeoutS = 0.05;
  CspShmMaster master(prefix, 0600, kTimeoutS);
  std::string error;
  ASSERT_TRUE(master.Connect(&error)) << error;
  CspFeedbacks feedback{};
  ASSERT_TRUE(master.Exchange(AllShutdown(), &feedback, &error)) << error;
  drives.server().StopDrivesClock(true);
  const auto stopped = std::chrono::steady_clock::now();
  bool ok = true;
  while (ok && std::chrono::steady_clock::now() - stopped < std::chrono::seconds(5)) {
    ok = master.Exchange(AllShutdown(), &feedback, &error);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_FALSE(ok) << "drives that latch nothing were never reported";
  EXPECT_GE(std::chrono::steady_clock::now() - stopped, std::chrono::duration<double>(kTimeoutS))
      << "reported before the response timeout: " << error;
  EXPECT_NE(error.find("silent"), std::string::npos) << error;
  EXPECT_NE(error.find(prefix), std::string::npos) << error;
  EXPECT_FALSE(master.connected());
  EXPECT_FALSE(master.Connect(&error)) << "drives that do not cycle were connected";
  EXPECT_NE(error.find("latched nothing"), std::string::npos) << error;
  drives.server().StopDrivesClock(false);
  EXPECT_TRUE(master.Connect(&error)) << error;
  EXPECT_TRUE(master.Exchange(AllShutdown(), &feedback, &error)) << error;
}

// The ring keeps a master's last RxPDOs after it is gone (a bridge that
// crashed while enabling): drives that start later must not act on them.
TEST(CspShmLink, RxPDOsWrittenBeforeTheDrivesStartedAreNotACommand) {
  const std::string prefix = Prefix("stale");
  auto writer = ShmWriter::Open(CspRxSpec(prefix, 0600));
  ASSERT_TRUE(writer.ok()) << writer.message;
  auto publish_shutdown = [&] {
    CspRxImage image{};
    const CspCommands c = AllShutdown();  // switch-on disabled → ready to switch on
    std::memcpy(image.drives, c.data(), sizeof image.drives);
    writer.value->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
      std::memcpy(buffer, &image, sizeof image);
      return sizeof image;
    });
  };
  publish_shutdown();
  Served drives(prefix);
  auto feedback_ring = ShmReader::Open(CspTxSpec(prefix, 0600));
  ASSERT_TRUE(feedback_ring.ok()) << feedback_ring.message;
  auto latest = [&] {
    CspTxImage image{};
    feedback_ring.value->Wait(std::chrono::milliseconds(100));
    feedback_ring.value->SkipToLatest();
    feedback_ring.value->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
      if (size != sizeof image) return false;
      std::memcpy(&image, data, sizeof image);
      return true;
    });
    return image;
  };
  std::this_thread::sleep_for(std::chrono::milliseconds(30));  // 30 of the drives' cycles
  CspTxImage seen = latest();
  ASSERT_GT(seen.drives[0].cycle_count, 1) << "the drives never cycled";
  for (const CspFeedback& f : seen.drives) {
    EXPECT_EQ(StateOfStatusword(f.statusword), State::kSwitchOnDisabled) << "an RxPDO from before was taken";
  }
  publish_shutdown();  // now a command
  for (int k = 0; k < 100 && StateOfStatusword(seen.drives[0].statusword) != State::kReadyToSwitchOn; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    seen = latest();
  }
  EXPECT_EQ(StateOfStatusword(seen.drives[0].statusword), State::kReadyToSwitchOn);
}

}  // namespace
}  // namespace edsp::cia402
