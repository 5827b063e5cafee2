// CiA 402 drives whose axes are a DriveBackend's drives (edsp-drive-sim in
// front of the virtual rig): a master enables them through the state
// machine and moves them in counts; the backend sees motor angles scaled by
// hand here (an independent computation of DriveScaling), stamped with the
// master's write; a drive out of operation holds its leg where it stopped
// following; a silent backend and a leg in fault reach the master as 603Fh.
#include <gtest/gtest.h>

#include "../actuator_bridge/recording_backend.h"
#include "edsp/drive_sim/backend_axes.h"
#include "edsp/drives/csp_master.h"
#include "edsp/drives/drive_cabinet.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/runtime.h"

namespace edsp::cia402 {
namespace {

constexpr double kCycle = 0.001;
constexpr std::int64_t kFieldbusTimeoutUs = 10'000'000;

// Drive d: 1000 counts per rad, offset 100·d, drives 1 and 4 mounted the other way.
std::array<DriveScaling, kCabinetDrives> Scaling() {
  std::array<DriveScaling, kCabinetDrives> s{};
  for (int d = 0; d < kCabinetDrives; ++d) {
    s[static_cast<std::size_t>(d)] = DriveScaling{1000.0, 100 * d, d == 1 || d == 4 ? -1 : 1};
  }
  return s;
}
double AngleByHand(int d, std::int32_t counts) {
  return (counts - 100.0 * d) / ((d == 1 || d == 4) ? -1000.0 : 1000.0);
}

class BackendAxesTest : public ::testing::Test {
 protected:
  BackendAxesTest() {
    auto backend = std::make_unique<RecordingBackend>();
    backend_ = backend.get();
    backend_->stopped_at = std::array<double, 6>{0.5, -0.25, 1.0, 0.0, 2.0, -1.5};  // where the legs stand
    SimulatedDriveOptions options;
    options.fieldbus_timeout_s = 10.0;
    options.following_error_window = 5000;
    cabinet_ = std::make_unique<DriveCabinet>(
        options, std::make_unique<BackendAxes>(std::move(backend), Huang2021Config(), Scaling(), kFieldbusTimeoutUs));
  }
  // One master cycle wanting `wanted` (counts per drive; nullopt: hold).
  // Drive `unattended` keeps its last controlword (nobody resets its fault).
  void Cycle(const std::array<std::optional<std::int32_t>, kCabinetDrives>& wanted, int unattended = -1) {
    std::array<CspCommand, kCabinetDrives> commands;
    for (int d = 0; d < kCabinetDrives; ++d) {
      const auto k = static_cast<std::size_t>(d);
      commands[k] = NextCspCommand(cabinet_->Feedback(d), controlwords_[k], wanted[k]);
      if (d == unattended) commands[k].controlword = controlwords_[k];
      controlwords_[k] = commands[k].controlword;
    }
    last_write_utime_ = UtimeNow();  // when the master's write arrived (the clock edsp-drive-sim stamps with)
    cabinet_->Command(commands, last_write_utime_);
    cabinet_->Tick(kCycle);
  }
  bool AllOperating() const {
    for (int d = 0; d < kCabinetDrives; ++d) {
      if (cabinet_->state(d) != State::kOperationEnabled) return false;
    }
    return true;
  }
  RecordingBackend* backend_ = nullptr;
  std::unique_ptr<DriveCabinet> cabinet_;
  std::array<std::uint16_t, kCabinetDrives> controlwords_{};
  std::int64_t last_write_utime_ = 0;
};

TEST_F(BackendAxesTest, EnabledWhereTheLegsStandThenTheTargetsReachTheBackendAsMotorAngles) {
  const std::array<double, 6> standing = *backend_->stopped_at;
  for (int d = 0; d < kCabinetDrives; ++d) {
    const double counts = 100.0 * d + ((d == 1 || d == 4) ? -1000.0 : 1000.0) * standing[static_cast<std::size_t>(d)];
    EXPECT_EQ(cabinet_->Feedback(d).position_actual, static_cast<std::int32_t>(counts)) << "drive " << d;
  }
  std::array<std::optional<std::int32_t>, kCabinetDrives> hold{};
  for (int k = 0; k < 10 && !AllOperating(); ++k) {
    Cycle(hold);
    EXPECT_EQ(backend_->written.motor_angle_rad, standing) << "enabling never moves a leg";
  }
  ASSERT_TRUE(AllOperating());
  backend_->stopped_at.reset();  // the legs now follow what they are told
  std::array<std::optional<std::int32_t>, kCabinetDrives> wanted;
  for (int d = 0; d < kCabinetDrives; ++d)
    wanted[static_cast<std::size_t>(d)] = cabinet_->Feedback(d).position_actual + 700 + d;
  Cycle(wanted);
  for (int d = 0; d < kCabinetDrives; ++d) {
    const auto k = static_cast<std::size_t>(d);
    EXPECT_NEAR(backend_->written.motor_angle_rad[k], AngleByHand(d, *wanted[k]), 1e-12) << "drive " << d;
    // Sampled at the cycle's start, before this write took effect.
    EXPECT_NE(cabinet_->Feedback(d).position_actual, *wanted[k]) << "drive " << d;
  }
  Cycle(wanted);
  for (int d = 0; d < kCabinetDrives; ++d) {
    const auto k = static_cast<std::size_t>(d);
    EXPECT_EQ(cabinet_->Feedback(d).position_actual, *wanted[k]) << "drive " << d << ": the leg's counts back";
  }
  EXPECT_EQ(backend_->written.utime, last_write_utime_) << "stamped with the master's write";
}

TEST_F(BackendAxesTest, ADriveOutOfOperationHoldsItsLegWhereItStoppedFollowing) {
  std::array<std::optional<std::int32_t>, kCabinetDrives> hold{};
  for (int k = 0; k < 10 && !AllOperating(); ++k) Cycle(hold);
  backend_->stopped_at.reset();
  std::array<std::optional<std::int32_t>, kCabinetDrives> wanted;
  for (int d = 0; d < kCabinetDrives; ++d)
    wanted[static_cast<std::size_t>(d)] = cabinet_->Feedback(d).position_actual + 900;
  Cycle(wanted);
  // The leg stands a little short of its target (a real axis lags): the
  // brake holds it there, not at the target.
  std::array<double, 6> actual = backend_->written.motor_angle_rad;
  actual[2] -= 0.002;
  backend_->stopped_at = actual;
  Cycle(wanted);
  const double stood = actual[2];
  ASSERT_NE(backend_->written.motor_angle_rad[2], stood);
  cabinet_->InjectFault(2, 0x2310);
  // The leg drifts in the backend's feedback meanwhile (another load on it).
  std::array<double, 6> drifting = backend_->written.motor_angle_rad;
  for (int k = 0; k < 5; ++k) {
    for (int d = 0; d < kCabinetDrives; ++d)
      wanted[static_cast<std::size_t>(d)] = *wanted[static_cast<std::size_t>(d)] + 10;
    Cycle(wanted, 2);
    drifting = actual;
    drifting[2] = stood + 0.001 * (k + 1);
    backend_->stopped_at = drifting;
    EXPECT_EQ(cabinet_->state(2), State::kFault);
    EXPECT_EQ(backend_->written.motor_angle_rad[2], stood) << "held where it stopped following, cycle " << k;
    EXPECT_EQ(backend_->written.motor_velocity_rad_s[2], 0.0);
    EXPECT_NEAR(backend_->written.motor_angle_rad[3], AngleByHand(3, *wanted[3]), 1e-12) << "the others run on";
  }
  EXPECT_EQ(cabinet_->Feedback(2).error_code, 0x2310);
}

// The simulator stopped (SIGSTOP, a long deschedule) while the legs, another
// process's physics, went on and came to rest elsewhere: on the first cycle
// after it, the drives' fieldbus timeout trips and each brakes where its leg
// stands then, not where it stood before the stall (which would command the
// platform back: a step).
TEST_F(BackendAxesTest, AfterAStallTheDrivesTimeOutAndHoldWhereTheLegsStandNow) {
  std::array<std::optional<std::int32_t>, kCabinetDrives> hold{};
  for (int k = 0; k < 10 && !AllOperating(); ++k) Cycle(hold);
  ASSERT_TRUE(AllOperating());
  backend_->stopped_at.reset();
  std::array<std::optional<std::int32_t>, kCabinetDrives> wanted;
  for (int d = 0; d < kCabinetDrives; ++d)
    wanted[static_cast<std::size_t>(d)] = cabinet_->Feedback(d).position_actual + 500;
  Cycle(wanted);
  Cycle(wanted);
  std::array<double, 6> rest = backend_->written.motor_angle_rad;
  for (double& angle : rest) angle += 0.003;  // ran on during the stall
  backend_->stopped_at = rest;
  cabinet_->Tick(11.0);  // the whole stall in one cycle, past the 10 s fieldbus timeout
  for (int d = 0; d < kCabinetDrives; ++d) {
    const auto k = static_cast<std::size_t>(d);
    EXPECT_EQ(cabinet_->state(d), State::kFault) << "drive " << d;
    EXPECT_EQ(cabinet_->Feedback(d).error_code, kErrorFieldbus) << "drive " << d;
    EXPECT_EQ(backend_->written.motor_angle_rad[k], rest[k]) << "drive " << d << " held where its leg stands now";
    EXPECT_EQ(backend_->written.motor_velocity_rad_s[k], 0.0);
  }
}

// The simulator stopped in the middle of a cycle, after its drives had
// decided to follow but before they wrote: on waking, that cycle's write
// would carry a target from before the stall. A command older than the
// drives' fieldbus timeout is not followed: each leg is held where it
// stands, as the drive would have stopped it then.
TEST_F(BackendAxesTest, ACommandOlderThanTheFieldbusTimeoutIsNeverFollowed) {
  std::array<std::optional<std::int32_t>, kCabinetDrives> hold{};
  for (int k = 0; k < 10 && !AllOperating(); ++k) Cycle(hold);
  ASSERT_TRUE(AllOperating());
  backend_->stopped_at.reset();
  std::array<CspCommand, kCabinetDrives> commands;
  for (int d = 0; d < kCabinetDrives; ++d) {
    const auto k = static_cast<std::size_t>(d);
    commands[k] = NextCspCommand(cabinet_->Feedback(d), controlwords_[k], cabinet_->Feedback(d).position_actual + 500);
  }
  cabinet_->Command(commands, UtimeNow());
  cabinet_->Tick(kCycle);
  std::array<double, 6> rest = backend_->written.motor_angle_rad;
  for (double& angle : rest) angle += 0.003;  // where the legs came to rest meanwhile
  backend_->stopped_at = rest;
  cabinet_->Command(commands, UtimeNow() - kFieldbusTimeoutUs - 1000);  // written before the stall
  cabinet_->Tick(kCycle);                                               // the drives' own clock saw one cycle pass
  for (int d = 0; d < kCabinetDrives; ++d) {
    const auto k = static_cast<std::size_t>(d);
    EXPECT_EQ(backend_->written.motor_angle_rad[k], rest[k])
        << "drive " << d << " followed a command from before the stall";
    EXPECT_EQ(backend_->written.motor_velocity_rad_s[k], 0.0);
  }
}

TEST_F(BackendAxesTest, ASilentBackendIsALostEncoderOnEveryDriveAndALegInFaultIsThatDrivesFault) {
  std::array<std::optional<std::int32_t>, kCabinetDrives> hold{};
  for (int k = 0; k < 10 && !AllOperating(); ++k) Cycle(hold);
  backend_->status[4] = DriveStatus::kFault;
  Cycle(hold);
  EXPECT_EQ(cabinet_->state(4), State::kFault);
  EXPECT_EQ(cabinet_->Feedback(4).error_code, kErrorDeviceHardware);
  EXPECT_EQ(cabinet_->state(0), State::kOperationEnabled);
  backend_->answering = false;
  Cycle(hold);
  for (int d = 0; d < kCabinetDrives; ++d) {
    EXPECT_EQ(cabinet_->state(d), State::kFault) << "drive " << d;
    if (d != 4) {
      EXPECT_EQ(cabinet_->Feedback(d).error_code, kErrorPositionSensor) << "drive " << d;
    }
  }
  // The backend answers again and the leg is fine: a fault reset brings every drive back.
  backend_->answering = true;
  backend_->status[4] = DriveStatus::kEnabled;
  for (int k = 0; k < 12 && !AllOperating(); ++k) Cycle(hold);
  EXPECT_TRUE(AllOperating());
}

TEST(BackendAxes, ADriveWithoutAScalingIsRefusedByName) {
  auto scaling = Scaling();
  scaling[3].counts_per_rad = 0.0;  // a config without [drives] counts_per_m
  try {
    BackendAxes axes(std::make_unique<RecordingBackend>(), Huang2021Config(), scaling, kFieldbusTimeoutUs);
    FAIL() << "a zero scaling would send NaN targets to the legs";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("leg 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("counts_per_m"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp::cia402
