// The virtual rig on a bus (memq://) and its process image (shared memory
// named for this test): what edsp-rig serves and publishes, cycle by cycle,
// at cycle times the test chooses, and on a clock of the test's own.
#include "edsp/rig/rig_loop.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "edsp/kinematics/config.h"
#include "edsp/node/fault.h"
#include "counting_clock.h"  // tests/support
#include "memq_bus.h"

namespace edsp {
namespace {

constexpr std::int64_t kLoopT0 = 1800000000000000;
constexpr std::int64_t kCycle = 1000;

std::string Prefix(const std::string& name) { return "edsp.rigloop." + name + "." + std::to_string(::getpid()); }

RigParameters Rig(double tracker_rate_hz = 1000.0) {
  RigParameters p = IdealRig(Huang2021Config());
  p.tracker.rate_hz = tracker_rate_hz;
  return p;
}

// The bridge's side of the image, as a test drives it.
class CommandImage {
 public:
  explicit CommandImage(const std::string& prefix) {
    auto writer = ShmWriter::Open(ShmChannelSpec{DriveCommandSegment(prefix), kDriveImageCommandFingerprint, 16,
                                                 sizeof(DriveImageCommand), 0600});
    EXPECT_TRUE(writer.ok()) << writer.message;
    writer_ = std::move(writer.value);
  }
  void Hold(const DriveFeedback& where, std::int64_t utime) {
    DriveImageCommand c{};
    c.utime = utime;
    c.cycle = ++cycle_;
    c.enable = 1;
    for (int i = 0; i < 6; ++i) c.motor_angle_rad[i] = where.motor_angle_rad[static_cast<std::size_t>(i)];
    writer_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
      std::memcpy(buffer, &c, sizeof c);
      return sizeof c;
    });
  }

 private:
  std::unique_ptr<ShmWriter> writer_;
  std::int64_t cycle_ = 0;
};

struct Fixture {
  explicit Fixture(const std::string& name, double tracker_rate_hz = 1000.0)
      : prefix(Prefix(name)),
        rig(Rig(tracker_rate_hz)),
        restore(RestoreFromImage(prefix, 0600, &rig)),
        image(prefix, 0600),
        bus(test_support::MemqConfig("rigloop_" + name)),
        loop(bus, rig, image, restore) {
    bus.Subscribe<rig_truth_t>("EDSP_RIG_TRUTH", [this](const rig_truth_t& t) { truths.push_back(t); });
    bus.Subscribe<tracker_point_t>("EDSP_TRACKER", [this](const tracker_point_t& t) { trackers.push_back(t); });
    bus.Subscribe<fault_t>("EDSP_FAULT", [this](const fault_t& f) { faults.push_back(f); });
  }
  void Cycles(int n) {
    for (int k = 0; k < n; ++k) {
      loop.RunCycle(now, 0);
      now += kCycle;
    }
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }

  std::string prefix;
  VirtualRig rig;
  ImageRestore restore;
  DriveImageServer image;
  Bus bus;
  RigLoop loop;
  std::int64_t now = kLoopT0;
  std::vector<rig_truth_t> truths;
  std::vector<tracker_point_t> trackers;
  std::vector<fault_t> faults;
};

TEST(RigLoop, EveryCycleWritesTheDrivesFeedbackAndTheTruthAndTheTrackerAtItsRate) {
  Fixture f("feedback", 100.0);
  auto reader = ShmReader::Open(
      ShmChannelSpec{f.image.feedback_segment(), kDriveImageFeedbackFingerprint, 16, sizeof(DriveImageFeedback), 0600});
  ASSERT_TRUE(reader.ok()) << reader.message;
  f.Cycles(100);
  std::vector<std::int64_t> cycles;
  DriveImageFeedback last{};
  while (reader.value->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
    std::memcpy(&last, data, size);
    return size == sizeof last;
  }) == TakeStatus::kMessage) {
    cycles.push_back(last.cycle);
  }
  ASSERT_FALSE(cycles.empty());
  EXPECT_EQ(cycles.back(), 100);
  EXPECT_EQ(last.utime, kLoopT0 + 99 * kCycle) << "stamped with the cycle's start";
  const DriveFeedback now = f.rig.Feedback();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(last.motor_angle_rad[i], now.motor_angle_rad[static_cast<std::size_t>(i)]);
  EXPECT_EQ(f.truths.size(), 100u);
  EXPECT_EQ(f.trackers.size(), 10u) << "100 Hz over 100 ms";
  EXPECT_TRUE(f.faults.empty());
}

// A wake five cycles late publishes the truth and the tracker for each cycle
// it missed, each stamped at its own instant, and the image carries the
// newest: the log shows no hole where the emulator's host stalled.
TEST(RigLoop, ALateWakePublishesEveryCycleItMissedAtItsOwnInstant) {
  Fixture f("latewake");
  CommandImage bridge(f.prefix);
  for (int k = 0; k < 10; ++k) {
    bridge.Hold(f.rig.Feedback(), f.now - 500);
    f.Cycles(1);
  }
  for (int k = 0; k < 6; ++k) bridge.Hold(f.rig.Feedback(), f.now - 500 + k * kCycle);  // the bridge ran on
  f.loop.RunCycle(f.now + 5 * kCycle + 300, 0);
  while (f.bus.Handle(std::chrono::milliseconds(0)) > 0) {
  }
  ASSERT_EQ(f.truths.size(), 16u);
  ASSERT_EQ(f.trackers.size(), 16u);
  for (std::size_t k = 0; k < f.truths.size(); ++k) {
    EXPECT_EQ(f.truths[k].utime, kLoopT0 + static_cast<std::int64_t>(k) * kCycle) << k;
    EXPECT_EQ(f.trackers[k].utime, f.truths[k].utime) << k;
  }
  auto reader = ShmReader::Open(
      ShmChannelSpec{f.image.feedback_segment(), kDriveImageFeedbackFingerprint, 16, sizeof(DriveImageFeedback), 0600});
  ASSERT_TRUE(reader.ok()) << reader.message;
  reader.value->RewindToLatest();
  DriveImageFeedback last{};
  ASSERT_EQ(reader.value->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
    std::memcpy(&last, data, size);
    return size == sizeof last;
  }),
            TakeStatus::kMessage);
  EXPECT_EQ(last.utime, kLoopT0 + 15 * kCycle) << "the newest cycle's instant, not the wake's";
  EXPECT_EQ(last.cycle, 16);
  EXPECT_TRUE(f.faults.empty());
}

// Enabled drives whose commands stop hold after the watchdog's 20 ms and
// say so once; commands again: said once more, as info.
TEST(RigLoop, DrivesWhoseCommandsStopReportHoldingOnceAndAgainWhenCommandsReturn) {
  Fixture f("watchdog");
  CommandImage bridge(f.prefix);
  f.Cycles(1);
  for (int k = 0; k < 5; ++k) {
    bridge.Hold(f.rig.Feedback(), f.now);
    f.Cycles(1);
  }
  EXPECT_TRUE(f.faults.empty());
  f.Cycles(40);  // no command for 40 ms
  ASSERT_EQ(f.faults.size(), 1u);
  EXPECT_EQ(f.faults[0].severity, fault_t::SEVERITY_ERROR);
  EXPECT_EQ(f.faults[0].channel, DriveCommandSegment(f.prefix));
  EXPECT_NE(f.faults[0].reason.find("drive watchdog: no drive command for"), std::string::npos) << f.faults[0].reason;
  bridge.Hold(f.rig.Feedback(), f.now);
  f.Cycles(1);
  ASSERT_EQ(f.faults.size(), 2u);
  EXPECT_EQ(f.faults[1].severity, fault_t::SEVERITY_INFO);
}

// A rig killed mid-run leaves its last feedback in the image; the next one
// continues from those motor angles (absolute encoders) and says so.
TEST(RigLoop, ARestartedRigContinuesFromItsKilledPredecessorsLastFeedback) {
  const std::string prefix = Prefix("restore");
  DriveFeedback left{};
  {
    VirtualRig moved(Rig());
    DriveSetpoint up;
    const DriveFeedback home = moved.Feedback();
    for (int i = 0; i < 6; ++i) up.motor_angle_rad[i] = home.motor_angle_rad[static_cast<std::size_t>(i)] + 3.0;
    moved.SetTarget(up, true);
    for (int k = 0; k < 2000; ++k) moved.Advance(1e-3);
    left = moved.Feedback();
  }
  const pid_t child = ::fork();
  if (child == 0) {  // the predecessor: writes its feedback and dies without cleaning up
    try {
      DriveImageServer image(prefix, 0600);
      image.PublishFeedback(left, kLoopT0, 1);
      ::_exit(0);
    } catch (...) {
      ::_exit(1);  // never back into the test runner
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);

  VirtualRig rig(Rig());
  const ImageRestore restore = RestoreFromImage(prefix, 0600, &rig);
  EXPECT_TRUE(restore.restored) << restore.note;
  EXPECT_NE(restore.note.find("continuing from the drives' last feedback"), std::string::npos) << restore.note;
  const DriveFeedback now = rig.Feedback();
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(now.motor_angle_rad[static_cast<std::size_t>(i)], left.motor_angle_rad[static_cast<std::size_t>(i)],
                1e-12);
  }
  Bus bus(test_support::MemqConfig("rigloop_restore"));
  std::vector<fault_t> faults;
  bus.Subscribe<fault_t>("EDSP_FAULT", [&](const fault_t& fault) { faults.push_back(fault); });
  {
    DriveImageServer image(prefix, 0600);  // claims the dead predecessor's ring
    RigLoop loop(bus, rig, image, restore);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].severity, fault_t::SEVERITY_INFO);
  EXPECT_EQ(faults[0].code, static_cast<std::int32_t>(FaultCode::kProcess));
  EXPECT_EQ(faults[0].channel, DriveFeedbackSegment(prefix));
}

// Run: a cycle per tick of the clock, its missed cycles on EDSP_STATUS.
TEST(RigLoop, RunStepsOnceATickAndReportsTheClocksMissedCycles) {
  Fixture f("run");
  std::vector<node_status_t> statuses;
  f.bus.Subscribe<node_status_t>("EDSP_STATUS", [&](const node_status_t& s) { statuses.push_back(s); });
  test_support::CountingClock clock(25, 7);
  f.loop.Run(clock, [&] { return clock.done(); });
  while (f.bus.Handle(std::chrono::milliseconds(0)) > 0) {
  }
  EXPECT_EQ(f.truths.size(), 25u);
  ASSERT_FALSE(statuses.empty());
  EXPECT_EQ(statuses[0].deadline_misses, 7);
}

TEST(RigLoop, NothingToRestoreWhenNoPredecessorLeftAnImage) {
  VirtualRig rig(Rig());
  const ImageRestore restore = RestoreFromImage(Prefix("nothing"), 0600, &rig);
  EXPECT_FALSE(restore.restored);
  EXPECT_TRUE(restore.note.empty()) << restore.note;
}

}  // namespace
}  // namespace edsp
