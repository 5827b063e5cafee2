// The bridge's CiA 402 backend against six simulated drives served on a
// thread, over each link that carries their image: Modbus TCP on loopback
// (edsp's server) and the shared-memory CSP image (edsp-drive-sim --serve
// shm's server). Over both: enabled where they stand, following the
// setpoints it is given within a count, a drive's fault reported with its
// code and never reset but by the operator's re-arm (Reset: the lifecycle's
// recovery from fault), an unfit setpoint refused, and drives that go away
// reported and reached again once they are back.
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "edsp/actuator_bridge/actuator_bridge.h"
#include "edsp/actuator_bridge/backend_registry.h"
#include "edsp/actuator_bridge/cia402_backend.h"
#include "edsp/drives/csp_shm_master.h"
#include "edsp/drives/csp_shm_server.h"
#include "edsp/drives/modbus_drive_master.h"
#include "edsp/node/fault.h"
#include "served_drives.h"

namespace edsp {
namespace {

using test_support::ServedDrives;

enum class Link { kModbus, kShm };

DrivesConfig ConfigFor(int port) {
  DrivesConfig c;
  c.backend = "modbus-tcp";
  c.port = port;
  c.response_timeout_s = 0.5;
  for (auto& s : c.scaling) s.counts_per_rad = 1048576.0 / (2.0 * M_PI);
  return c;
}

// Six drives served over `link` on a thread while it lives (destroying it
// is the simulator going away); a new one at the same port or prefix is
// the simulator back.
class Cabinet {
 public:
  explicit Cabinet(Link link, double cycle_s = 0.001, int port = 0, std::string prefix = "")
      : link_(link), prefix_(prefix.empty() ? NewPrefix() : std::move(prefix)) {
    if (link == Link::kModbus) {
      modbus_ = std::make_unique<ServedDrives>(port, cycle_s);
      port_ = modbus_->port();
      return;
    }
    cia402::ShmDriveServerOptions options;
    options.prefix = prefix_;
    options.cycle_s = cycle_s;
    options.drive.fieldbus_timeout_s = 2.0;  // the tests' cycles are paced by a busy machine, not 1 ms
    shm_ = std::make_unique<cia402::CspShmServer>(options);
    thread_ = std::thread([this] { shm_->Run([this] { return stop_.load(); }); });
  }
  ~Cabinet() {
    if (!thread_.joinable()) return;
    stop_ = true;
    thread_.join();
  }
  Cabinet(const Cabinet&) = delete;
  Cabinet& operator=(const Cabinet&) = delete;

  void InjectFault(int index, std::uint16_t code) {
    if (modbus_)
      modbus_->server().InjectFault(index, code);
    else
      shm_->InjectFault(index, code);
  }
  void StopDrivesClock(bool stopped) {
    if (modbus_)
      modbus_->server().StopDrivesClock(stopped);
    else
      shm_->StopDrivesClock(stopped);
  }
  // What a report about these drives names.
  std::string where() const { return link_ == Link::kModbus ? "127.0.0.1:" + std::to_string(port_) : prefix_; }
  int port() const { return port_; }
  const std::string& prefix() const { return prefix_; }

 private:
  static std::string NewPrefix() {
    static int count = 0;
    return fmt::format("edsp.test.{}.cia402.{}", ::getpid(), ++count);
  }

  Link link_;
  std::string prefix_;
  int port_ = 0;
  std::unique_ptr<ServedDrives> modbus_;
  std::unique_ptr<cia402::CspShmServer> shm_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// `link` to the drives at `port` (Modbus) or `prefix` (shm).
std::unique_ptr<cia402::CspLink> LinkTo(Link link, int port, const std::string& prefix) {
  const DrivesConfig c = ConfigFor(port);
  if (link == Link::kModbus) return std::make_unique<cia402::ModbusDriveMaster>(c.host, c.port, c.response_timeout_s);
  return std::make_unique<cia402::CspShmMaster>(prefix, 0600, c.response_timeout_s);
}

// A backend over `link` to the drives at `port` (Modbus) or `prefix` (shm).
std::unique_ptr<Cia402Backend> BackendTo(Link link, int port, const std::string& prefix) {
  return std::make_unique<Cia402Backend>(ConfigFor(port), LinkTo(link, port, prefix));
}

std::unique_ptr<Cia402Backend> BackendTo(Link link, const Cabinet& drives) {
  return BackendTo(link, drives.port(), drives.prefix());
}

// Until the drives have run `cycles` more of their cycles (read over a link
// of its own, by the cycle count their image carries): what a test needs
// of the drives' clock, whatever the machine's speed. Fails after 10 s.
void WaitForDriveCycles(Link link, const Cabinet& drives, int cycles) {
  auto observer = LinkTo(link, drives.port(), drives.prefix());
  std::string error;
  ASSERT_TRUE(observer->Connect(&error)) << error;
  cia402::CspFeedbacks feedback{};
  ASSERT_TRUE(observer->ReadFeedback(&feedback, &error)) << error;
  const std::uint16_t start = feedback[0].cycle_count;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (static_cast<std::uint16_t>(feedback[0].cycle_count - start) < cycles) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the drives stopped cycling";
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(observer->ReadFeedback(&feedback, &error)) << error;
  }
}

// Once the drives have taken the last commands: each shut down (ready to
// switch on), read over a link of its own.
void ExpectTheDrivesWithoutPower(Link link, const Cabinet& drives) {
  ASSERT_NO_FATAL_FAILURE(WaitForDriveCycles(link, drives, 3));
  auto observer = LinkTo(link, drives.port(), drives.prefix());
  std::string error;
  ASSERT_TRUE(observer->Connect(&error)) << error;
  cia402::CspFeedbacks feedback{};
  ASSERT_TRUE(observer->ReadFeedback(&feedback, &error)) << error;
  for (std::size_t d = 0; d < feedback.size(); ++d) {
    EXPECT_EQ(cia402::StateOfStatusword(feedback[d].statusword), cia402::State::kReadyToSwitchOn) << "drive " << d + 1;
  }
}

class Cia402Backends : public ::testing::TestWithParam<Link> {};

// --backend modbus-tcp over a config whose [drives] declares no encoder
// counts: refused at configure, naming the leg and the key to set, never
// sending NaN targets.
TEST(Cia402Backend, ADriveWithoutAScalingIsRefusedByNameAtConfigure) {
  DrivesConfig c = ConfigFor(1502);
  c.scaling[2].counts_per_rad = 0.0;
  Cia402Backend backend(c, std::make_unique<cia402::ModbusDriveMaster>(c.host, c.port, c.response_timeout_s));
  std::string error;
  EXPECT_FALSE(backend.Configure(Huang2021Config(), &error));
  EXPECT_NE(error.find("[drives] leg 3"), std::string::npos) << error;
  EXPECT_NE(error.find("counts_per_m"), std::string::npos) << error;
  EXPECT_EQ(backend.state(), BackendState::kUnconfigured) << "a failed configure leaves it as it was";
}

std::size_t Backend_Detail_Disabled(const Cia402Backend& backend) {
  return backend.Detail().find("drive 1 in switch on disabled");
}

std::int64_t Now() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A ramp of every leg, 0.01 rad a cycle up to `to[leg]`, in the bridge's
// order (read, then write): a jump beyond the drives' following window
// would fault them, as it should. Returns the last setpoint written.
DriveSetpoint Ramp(Cia402Backend* backend, const std::array<double, 6>& to) {
  DriveSetpoint setpoint;
  DriveFeedback f;
  const double furthest = *std::max_element(to.begin(), to.end());
  for (int k = 1; 0.01 * (k - 1) < furthest; ++k) {
    for (int i = 0; i < 6; ++i) setpoint.motor_angle_rad[i] = std::min(0.01 * k, to[i]);
    backend->Read(Now(), &f);
    backend->Write(Now(), setpoint);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return setpoint;
}

// Cycles of the bridge's order (read, then write) until `until` or `limit`.
template <typename Until>
DriveFeedback Cycles(Cia402Backend* backend, const DriveSetpoint& setpoint, Until until, int limit = 300) {
  DriveFeedback f;
  for (int k = 0; k < limit; ++k) {
    backend->Read(Now(), &f);
    backend->Write(Now(), setpoint);
    if (until(f)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return f;
}

TEST_P(Cia402Backends, EnablesTheDrivesAndFollowsTheSetpointsWithinACount) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error)) << error;
  ASSERT_TRUE(backend.Activate(&error)) << error;
  EXPECT_EQ(backend.state(), BackendState::kActive);
  const DriveSetpoint setpoint = Ramp(&backend, {0.5, 1.0, 1.5, 2.0, 2.5, 3.0});
  const DriveFeedback f = Cycles(&backend, setpoint, [&](const DriveFeedback& fb) {
    return std::abs(fb.motor_angle_rad[5] - setpoint.motor_angle_rad[5]) < 1e-5;
  });
  const double count_rad = 2.0 * M_PI / 1048576.0;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(f.motor_angle_rad[i], setpoint.motor_angle_rad[i], count_rad) << "leg " << i + 1;
    EXPECT_EQ(f.status[i], DriveStatus::kEnabled);
  }
  EXPECT_EQ(backend.Detail(), "");
}

TEST_P(Cia402Backends, ADrivesFaultIsReportedAndResetOnlyByAReArm) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveSetpoint home;
  drives.InjectFault(3, 0x7500);
  DriveFeedback f = Cycles(&backend, home, [](const DriveFeedback& fb) { return fb.status[3] == DriveStatus::kFault; });
  EXPECT_EQ(f.status[3], DriveStatus::kFault);
  EXPECT_NE(backend.Detail().find("drive 4 in fault (error code 7500h)"), std::string::npos) << backend.Detail();
  EXPECT_EQ(backend.state(), BackendState::kFault);
  // Many cycles later it is still in fault: the backend never resets it.
  f = Cycles(
      &backend, home, [](const DriveFeedback&) { return false; }, 50);
  EXPECT_EQ(f.status[3], DriveStatus::kFault);
  EXPECT_EQ(f.status[2], DriveStatus::kEnabled) << "the others run on";
  EXPECT_FALSE(backend.Read(Now(), &f)) << "a drive out of operation fails the cycle: the bridge holds";
  ASSERT_TRUE(backend.Reset(&error)) << error;  // the operator's re-arm
  EXPECT_EQ(backend.state(), BackendState::kActive) << "recovered";
  f = Cycles(&backend, home, [](const DriveFeedback& fb) { return fb.status[3] == DriveStatus::kEnabled; });
  EXPECT_EQ(f.status[3], DriveStatus::kEnabled);
  EXPECT_EQ(backend.Detail(), "");
}

// In fault the backend keeps cycling but takes no new target: the drives
// still in operation hold the last one it took, at rest, whatever the
// setpoints say, until a re-arm recovers it.
TEST_P(Cia402Backends, InFaultItTakesNoNewTargetUntilAReArmRecoversIt) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveSetpoint held = Ramp(&backend, {0.2, 0.2, 0.2, 0.2, 0.2, 0.2});
  Cycles(&backend, held, [&](const DriveFeedback& fb) { return std::abs(fb.motor_angle_rad[0] - 0.2) < 1e-5; });
  drives.InjectFault(5, 0x7500);
  Cycles(&backend, held, [&](const DriveFeedback&) { return backend.state() == BackendState::kFault; });
  ASSERT_EQ(backend.state(), BackendState::kFault) << backend.Detail();
  DriveSetpoint further = held;
  further.motor_angle_rad.fill(0.21);  // within the following window
  further.motor_velocity_rad_s.fill(1.0);
  DriveFeedback f = Cycles(
      &backend, further, [](const DriveFeedback&) { return false; }, 50);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(f.motor_angle_rad[i], 0.2, 1e-5) << "leg " << i + 1 << " moved while the backend was in fault";
    EXPECT_EQ(f.status[i], DriveStatus::kEnabled) << "leg " << i + 1;
  }
  EXPECT_FALSE(backend.Write(Now(), further));
  ASSERT_TRUE(backend.Reset(&error)) << error;
  EXPECT_EQ(backend.state(), BackendState::kActive);
  further.motor_velocity_rad_s.fill(0.0);
  f = Cycles(&backend, further, [](const DriveFeedback& fb) { return std::abs(fb.motor_angle_rad[0] - 0.21) < 1e-5; });
  EXPECT_NEAR(f.motor_angle_rad[0], 0.21, 1e-5) << "recovered, it takes targets again";
}

// The lifecycle's other ends: a re-arm needs a cycling backend; deactivate
// and cleanup let the drives and the link go, and it can be configured
// and activated again.
TEST_P(Cia402Backends, DeactivatedAndCleanedUpItStartsAgainAndRefusesAReArmMeanwhile) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  EXPECT_FALSE(backend.Reset(&error));
  EXPECT_EQ(error, "cannot recover a backend that is unconfigured");
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  EXPECT_FALSE(backend.Configure(PlatformConfig{}, &error));
  EXPECT_EQ(error, "cannot configure a backend that is active");
  backend.Deactivate();
  EXPECT_EQ(backend.state(), BackendState::kInactive);
  EXPECT_FALSE(backend.Write(Now(), DriveSetpoint{})) << "no cycle while inactive";
  EXPECT_FALSE(backend.Reset(&error));
  EXPECT_EQ(error, "cannot recover a backend that is inactive");
  backend.Cleanup();
  EXPECT_EQ(backend.state(), BackendState::kUnconfigured);
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveFeedback f;
  EXPECT_TRUE(backend.Read(Now(), &f)) << backend.Detail();
  EXPECT_TRUE(backend.Write(Now(), DriveSetpoint{})) << backend.Detail();
}

// A bridge that stops cleanly leaves its drives without power (shutdown:
// ready to switch on), even when it exits the moment it has deactivated
// them: its last RxPDOs are taken after it is gone.
TEST_P(Cia402Backends, DeactivatedThenGoneItLeavesTheDrivesWithoutPower) {
  Cabinet drives(GetParam());
  {
    auto backend = BackendTo(GetParam(), drives);
    std::string error;
    ASSERT_TRUE(backend->Configure(PlatformConfig{}, &error) && backend->Activate(&error)) << error;
    DriveFeedback f;
    EXPECT_TRUE(backend->Read(Now(), &f)) << backend->Detail();
    backend->Deactivate();
    backend->Cleanup();
  }
  ExpectTheDrivesWithoutPower(GetParam(), drives);
}

// The backend as the bridge's main holds it (ActiveBackend, by its
// registry name): an exception out of the loop still deactivates it.
TEST_P(Cia402Backends, AnActiveBackendLeftByAnExceptionLeavesTheDrivesWithoutPower) {
  Cabinet drives(GetParam());
  const DrivesConfig config = ConfigFor(drives.port());
  const TransportConfig transport;
  const std::string name = GetParam() == Link::kModbus ? "modbus-tcp" : "cia402-shm";
  try {
    std::string note;
    const ActiveBackend backend(name, BackendContext{config, transport, drives.prefix()}, PlatformConfig{}, &note);
    EXPECT_EQ(backend->state(), BackendState::kActive);
    DriveFeedback f;
    EXPECT_TRUE(backend->Read(Now(), &f)) << backend->Detail();
    throw std::runtime_error("the loop failed");
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the loop failed");
  }
  ExpectTheDrivesWithoutPower(GetParam(), drives);
  std::string note;
  try {
    const ActiveBackend unknown("ethercat", BackendContext{config, transport, drives.prefix()}, PlatformConfig{},
                                &note);
    ADD_FAILURE() << "an unknown backend was made";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--backend ethercat: known backends: " + KnownBackends()), std::string::npos)
        << e.what();
  }
}

// The TxPDO a request reads was latched at the drives' last cycle, before
// the commands it carries: drives on a clock 100× slower than the master's
// requests still answer "operation enabled" for a while after the
// deactivation's shutdown. Activation must not take that for its own
// drives enabled; it waits for feedback latched after its commands (the
// drives' cycle count, register 7), so the first cycle finds them in
// operation.
TEST_P(Cia402Backends, ActivationTrustsOnlyFeedbackLatchedAfterItsCommands) {
  Cabinet drives(GetParam(), 0.1);
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  for (int activation = 1; activation <= 3; ++activation) {
    ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error))
        << "activation " << activation << ": " << error;
    std::this_thread::sleep_for(std::chrono::milliseconds(210));  // two of the drives' cycles
    DriveFeedback f;
    EXPECT_TRUE(backend.Read(Now(), &f)) << "activation " << activation << ": " << backend.Detail();
    EXPECT_TRUE(backend.Write(Now(), DriveSetpoint{})) << "activation " << activation << ": " << backend.Detail();
    std::this_thread::sleep_for(std::chrono::milliseconds(210));
    EXPECT_TRUE(backend.Read(Now(), &f)) << "activation " << activation << ": " << backend.Detail();
    for (int i = 0; i < 6; ++i) EXPECT_EQ(f.status[i], DriveStatus::kEnabled) << "leg " << i + 1;
    backend.Deactivate();
    backend.Cleanup();
  }
}

// Drives that answer but no longer cycle (their clock stopped behind a
// gateway): a re-arm cannot tell their state and fails within its budget,
// naming it, and succeeds once they cycle again.
TEST_P(Cia402Backends, AReArmOfDrivesThatStoppedCyclingFailsNamingIt) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  drives.InjectFault(1, 0x7500);
  Cycles(&backend, DriveSetpoint{}, [&](const DriveFeedback&) { return backend.state() == BackendState::kFault; });
  ASSERT_EQ(backend.state(), BackendState::kFault);
  drives.StopDrivesClock(true);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(backend.Reset(&error));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2)) << "a re-arm holds the cycle up";
  EXPECT_NE(error.find("not cycling"), std::string::npos) << error;
  EXPECT_EQ(backend.state(), BackendState::kFault);
  drives.StopDrivesClock(false);
  EXPECT_TRUE(backend.Reset(&error)) << error;
  EXPECT_EQ(backend.state(), BackendState::kActive);
}

TEST_P(Cia402Backends, AStartUpResetsNoFaultAndAReArmResetsOnlyTheFaultedDrive) {
  Cabinet drives(GetParam());
  {
    // A predecessor left the drives enabled at 1 rad; then drive 5 faulted.
    auto before_owner = BackendTo(GetParam(), drives);
    Cia402Backend& before = *before_owner;
    std::string error;
    ASSERT_TRUE(before.Configure(PlatformConfig{}, &error) && before.Activate(&error)) << error;
    Ramp(&before, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0});
    drives.InjectFault(4, 0x8130);
  }
  ASSERT_NO_FATAL_FAILURE(WaitForDriveCycles(GetParam(), drives, 2));  // a drive cycle raises the fault
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveFeedback f;
  EXPECT_FALSE(backend.Read(Now(), &f)) << "a drive found in fault fails the first cycle: the bridge holds";
  EXPECT_EQ(f.status[4], DriveStatus::kFault) << "start-up resets no fault";
  EXPECT_NE(backend.Detail().find("drive 5 in fault (error code 8130h)"), std::string::npos) << backend.Detail();
  for (int i : {0, 1, 2, 3, 5}) EXPECT_EQ(f.status[i], DriveStatus::kEnabled) << "leg " << i + 1;
  const DriveFeedback held = f;
  ASSERT_TRUE(backend.Reset(&error)) << error;  // the operator's re-arm
  EXPECT_TRUE(backend.Read(Now(), &f)) << backend.Detail();
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(f.status[i], DriveStatus::kEnabled) << "leg " << i + 1;
    EXPECT_NEAR(f.motor_angle_rad[i], held.motor_angle_rad[i], 1e-5) << "leg " << i + 1 << " moved";
  }
}

TEST_P(Cia402Backends, ASetpointThatDoesNotFitTheCountsIsRefusedAndTheLastStays) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveSetpoint good;
  good.motor_angle_rad.fill(1.0);
  Cycles(&backend, good, [](const DriveFeedback& fb) { return std::abs(fb.motor_angle_rad[0] - 1.0) < 1e-5; });
  DriveSetpoint bad = good;
  bad.motor_angle_rad[2] = NAN;
  EXPECT_FALSE(backend.Write(Now(), bad));
  EXPECT_NE(backend.Detail().find("leg 3"), std::string::npos) << backend.Detail();
  bad.motor_angle_rad[2] = 1e6;  // far beyond 2^31 counts
  EXPECT_FALSE(backend.Write(Now(), bad));
  DriveFeedback f;
  for (int k = 0; k < 20; ++k) {  // cycles carrying the bad target: each refused, the good one in force
    backend.Read(Now(), &f);
    EXPECT_FALSE(backend.Write(Now(), bad));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  backend.Read(Now(), &f);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(f.motor_angle_rad[i], 1.0, 1e-5) << "leg " << i + 1;
}

// One cycle in the bridge's order, holding where the drives were enabled:
// Read (the last exchange's answer, or a reconnect), then Write (the exchange).
bool OneCycle(Cia402Backend* backend, DriveFeedback* f) {
  const bool read = backend->Read(Now(), f);
  return backend->Write(Now(), DriveSetpoint{}) && read;
}

TEST_P(Cia402Backends, AServerThatGoesAwayIsReportedAndReachedAgain) {
  auto drives = std::make_unique<Cabinet>(GetParam());
  const int port = drives->port();
  const std::string prefix = drives->prefix(), where = drives->where();
  auto backend_owner = BackendTo(GetParam(), port, prefix);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  DriveFeedback f;
  EXPECT_TRUE(OneCycle(&backend, &f)) << backend.Detail();
  drives.reset();
  EXPECT_FALSE(OneCycle(&backend, &f)) << "the exchange fails on the wire";
  EXPECT_NE(backend.Detail().find(where), std::string::npos) << backend.Detail();
  EXPECT_FALSE(backend.Read(Now(), &f)) << "the next cycle's read: disconnected";
  for (int i = 0; i < 6; ++i) EXPECT_EQ(f.status[i], DriveStatus::kDisabled);
  drives = std::make_unique<Cabinet>(GetParam(), 0.001, port, prefix);
  // Reconnected within the 100 ms retry: the cycle then fails on the drives, not the wire.
  bool back = false;
  for (int k = 0; k < 100 && backend.Detail().find("switch on disabled") == std::string::npos; ++k) {
    back = backend.Read(Now(), &f);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_FALSE(back) << "a new server's drives start disabled: not in operation until re-armed";
  EXPECT_NE(Backend_Detail_Disabled(backend), std::string::npos) << backend.Detail();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(f.status[i], DriveStatus::kDisabled);
  ASSERT_TRUE(backend.Reset(&error)) << error;
  EXPECT_TRUE(OneCycle(&backend, &f)) << backend.Detail();
}

TEST_P(Cia402Backends, NobodyServingFailsActivationWithTheEndpoint) {
  int port = 0;
  std::string prefix, where;
  {
    Cabinet gone(GetParam());
    port = gone.port();
    prefix = gone.prefix();
    where = gone.where();
  }
  auto backend = BackendTo(GetParam(), port, prefix);
  std::string error;
  ASSERT_TRUE(backend->Configure(PlatformConfig{}, &error));
  EXPECT_FALSE(backend->Activate(&error));
  EXPECT_NE(error.find(where), std::string::npos) << error;
}

// The bridge these tests run over the drives (session 7).
std::unique_ptr<ActuatorBridge> BridgeOver(Cia402Backend* backend) {
  BridgeOptions options;
  options.session_id = 7;
  return std::make_unique<ActuatorBridge>(PlatformModel(Huang2021Config()), backend, options);
}

// The bridge over Modbus drives: a drive's fault holds and latches the
// bridge with the drive and its code in the fault, and the operator's
// re-arm resets the drive and lets the stream through again.
TEST_P(Cia402Backends, ADriveFaultLatchesTheBridgeAndItsReArmResetsTheDrive) {
  Cabinet drives(GetParam());
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  std::unique_ptr<ActuatorBridge> bridge_owner = BridgeOver(&backend);
  ActuatorBridge& bridge = *bridge_owner;
  leg_state_t state;
  fault_t fault;
  std::int64_t t = Now();
  for (int k = 0; k < 20; ++k, t += 1000) bridge.Cycle(t, &state, &fault);
  drives.InjectFault(1, 0x2310);
  bool raised = false;
  for (int k = 0; k < 200 && !raised; ++k, t += 1000) {
    raised = bridge.Cycle(t, &state, &fault);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(raised);
  EXPECT_EQ(fault.code, static_cast<std::int32_t>(FaultCode::kBackend));
  EXPECT_NE(fault.reason.find("drive 2 in fault (error code 2310h)"), std::string::npos) << fault.reason;
  EXPECT_TRUE(bridge.holding());
  ASSERT_TRUE(bridge.Rearm(&error)) << error;
  bool answers = false;
  for (int k = 0; k < 50 && !answers; ++k, t += 1000) {
    answers = bridge.Cycle(t, &state, &fault) && fault.reason.find("answers again") != std::string::npos;
  }
  EXPECT_TRUE(answers) << fault.reason;
  EXPECT_EQ(state.drive_status[1], leg_state_t::DRIVE_HOLDING) << "enabled, holding until the stream rejoins";
}

// A drive found in fault at start-up puts the backend in fault at the
// bridge's first read, before any cycle: an operator's re-arm right then
// must reset it, not confirm a bridge that "was not latched".
TEST_P(Cia402Backends, AReArmBeforeTheFirstCycleResetsADriveFoundInFault) {
  Cabinet drives(GetParam());
  drives.InjectFault(2, 0x7500);
  ASSERT_NO_FATAL_FAILURE(WaitForDriveCycles(GetParam(), drives, 2));  // a drive cycle raises it
  auto backend_owner = BackendTo(GetParam(), drives);
  Cia402Backend& backend = *backend_owner;
  std::string error;
  ASSERT_TRUE(backend.Configure(PlatformConfig{}, &error) && backend.Activate(&error)) << error;
  std::unique_ptr<ActuatorBridge> bridge_owner = BridgeOver(&backend);
  ActuatorBridge& bridge = *bridge_owner;
  ASSERT_EQ(backend.state(), BackendState::kFault) << backend.Detail();
  ASSERT_TRUE(bridge.Rearm(&error)) << error;
  EXPECT_EQ(backend.state(), BackendState::kActive) << "the re-arm reset the drive";
  DriveFeedback f;
  EXPECT_TRUE(backend.Read(Now(), &f)) << backend.Detail();
  EXPECT_EQ(f.status[2], DriveStatus::kEnabled);
}

INSTANTIATE_TEST_SUITE_P(Links, Cia402Backends, ::testing::Values(Link::kModbus, Link::kShm),
                         [](const ::testing::TestParamInfo<Link>& link) {
                           return link.param == Link::kModbus ? std::string("ModbusTcp") : std::string("SharedMemory");
                         });

}  // namespace
}  // namespace edsp
