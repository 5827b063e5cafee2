// The virtual rig's backend on a real shared-memory image: drives silent
// while the bridge keeps its time fail a read at the timeout, as before; a
// stall of the whole host (bridge and drives alike, 49 ms) is no outage.

#include "edsp/actuator_bridge/virtual_rig_backend.h"

#include <unistd.h>

#include <atomic>
#include <cstring>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"

namespace edsp {
namespace {

constexpr std::int64_t kTimeoutUs = 50'000;

class VirtualRigBackendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ShmChannelSpec spec{DriveFeedbackSegment(prefix_), kDriveImageFeedbackFingerprint, 16, sizeof(DriveImageFeedback),
                        0600};
    auto writer = ShmWriter::Open(spec);
    ASSERT_TRUE(writer.ok()) << writer.message;
    drives_ = std::move(writer.value);
    std::string error;
    ASSERT_TRUE(backend_.Configure(Huang2021Config(), &error)) << error;
    // Activation waits for an image written after it attached.
    std::atomic<bool> active{false};
    std::thread drives([&] {
      while (!active) {
        Answer();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
    const bool activated = backend_.Activate(&error);
    active = true;
    drives.join();
    ASSERT_TRUE(activated) << error;
  }
  void TearDown() override {
    backend_.Deactivate();
    backend_.Cleanup();
  }

  void Answer() {
    DriveImageFeedback f{};
    f.cycle = ++cycle_;
    for (auto& s : f.status) s = static_cast<std::int8_t>(DriveStatus::kEnabled);
    drives_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
      std::memcpy(buffer, &f, sizeof f);
      return sizeof f;
    });
  }

  // Reads every `period_us` from `from_us` while the drives say nothing;
  // the bridge's clock of the first read that fails, or -1.
  std::int64_t FirstFailedRead(std::int64_t from_us, std::int64_t period_us, std::int64_t until_us) {
    DriveFeedback feedback;
    for (std::int64_t now = from_us; now <= until_us; now += period_us) {
      if (!backend_.Read(now, &feedback)) return now;
    }
    return -1;
  }

  const std::string prefix_ = "edsp.test.vrb." + std::to_string(::getpid());
  std::unique_ptr<ShmWriter> drives_;
  VirtualRigBackend backend_{prefix_, 0600, kTimeoutUs};
  std::int64_t cycle_ = 0;
};

constexpr std::int64_t kT0 = 5'000'000;

TEST_F(VirtualRigBackendTest, DrivesSilentWhileTheBridgeKeepsItsTimeFailAtTheTimeout) {
  Answer();
  DriveFeedback feedback;
  ASSERT_TRUE(backend_.Read(kT0, &feedback));
  EXPECT_EQ(FirstFailedRead(kT0 + 1000, 1000, kT0 + 200'000), kT0 + kTimeoutUs + 1000);
  EXPECT_NE(backend_.Detail().find("no feedback through 50 ms"), std::string::npos) << backend_.Detail();
  // Drives that answer again are read again.
  Answer();
  EXPECT_TRUE(backend_.Read(kT0 + 200'000, &feedback));
  EXPECT_EQ(backend_.Detail(), "");
}

TEST_F(VirtualRigBackendTest, AStallOfTheWholeHostIsNoDriveOutage) {
  Answer();
  DriveFeedback feedback;
  ASSERT_TRUE(backend_.Read(kT0, &feedback));
  // Bridge and drives stood 49 ms; the bridge looks first on waking, and the
  // drives' catch-up takes a few of its cycles more.
  EXPECT_EQ(FirstFailedRead(kT0 + 49'000, 1000, kT0 + 49'000 + 10'000), -1);
  Answer();
  EXPECT_TRUE(backend_.Read(kT0 + 60'000, &feedback));
  // Even a pause past the timeout itself: the drives went on meanwhile or
  // stopped on their own watchdog, which their next image says.
  EXPECT_EQ(FirstFailedRead(kT0 + 300'000, 1000, kT0 + 300'000 + 10'000), -1);
}

TEST_F(VirtualRigBackendTest, ADriveInFaultFailsTheReadAndIsNamed) {
  DriveImageFeedback f{};
  for (auto& s : f.status) s = static_cast<std::int8_t>(DriveStatus::kEnabled);
  f.status[3] = static_cast<std::int8_t>(DriveStatus::kFault);
  drives_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
    std::memcpy(buffer, &f, sizeof f);
    return sizeof f;
  });
  DriveFeedback feedback;
  EXPECT_FALSE(backend_.Read(kT0, &feedback));
  EXPECT_EQ(backend_.Detail(), "drive 4 in fault (braked)");
}

}  // namespace
}  // namespace edsp
