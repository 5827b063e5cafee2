// The simulated CSP drive as a master sees it: enabled through the state
// machine by NextCspCommand, it follows its target and stands otherwise;
// it faults on a following error, on a silent fieldbus and on demand, and
// comes back only through a fault reset.
#include <gtest/gtest.h>

#include "edsp/drives/csp_master.h"
#include "edsp/drives/simulated_csp_drive.h"

namespace edsp::cia402 {
namespace {

constexpr double kCycle = 0.001;

// Cycles of a master that wants `wanted` (empty: hold) until `until` holds.
template <typename Until>
int Cycles(SimulatedCspDrive* drive, std::uint16_t* controlword, std::optional<std::int32_t> wanted, Until until,
           int limit = 100) {
  int n = 0;
  for (; n < limit && !until(); ++n) {
    const CspCommand c = NextCspCommand(drive->Feedback(), *controlword, wanted);
    *controlword = c.controlword;
    drive->Command(c);
    drive->Step(kCycle);
  }
  return n;
}

TEST(SimulatedCspDrive, EnabledByTheMasterWithoutMovingThenFollowsItsTarget) {
  SimulatedCspDrive drive({}, 5000);
  std::uint16_t cw = 0;
  const int enabling = Cycles(&drive, &cw, 90000, [&] { return drive.state() == State::kOperationEnabled; });
  EXPECT_LE(enabling, 4);
  EXPECT_EQ(drive.Feedback().position_actual, 5000) << "enabling never moves the axis";
  Cycles(
      &drive, &cw, 90000, [&] { return drive.Feedback().position_actual == 90000; }, 10);
  EXPECT_EQ(drive.Feedback().position_actual, 90000);
  EXPECT_NE(drive.Feedback().statusword & kStatusTargetReached, 0);
  EXPECT_EQ(drive.Feedback().mode_display, kModeCyclicSynchronousPosition);
}

TEST(SimulatedCspDrive, ATargetBeyondTheFollowingWindowFaultsTheDriveWhichThenStands) {
  SimulatedDriveOptions options;
  options.max_speed_counts_s = 1e6;  // 1000 counts a cycle
  options.following_error_window = 5000;
  SimulatedCspDrive drive(options);
  std::uint16_t cw = 0;
  Cycles(&drive, &cw, 0, [&] { return drive.state() == State::kOperationEnabled; });
  CspCommand jump = NextCspCommand(drive.Feedback(), cw, 100000);
  drive.Command(jump);
  drive.Step(kCycle);
  drive.Step(kCycle);
  EXPECT_EQ(drive.state(), State::kFault);
  EXPECT_EQ(drive.Feedback().error_code, kErrorFollowing);
  EXPECT_EQ(StateOfStatusword(drive.Feedback().statusword), State::kFault);
  const std::int32_t stood = drive.Feedback().position_actual;
  for (int k = 0; k < 10; ++k) {
    drive.Command(jump);
    drive.Step(kCycle);
  }
  EXPECT_EQ(drive.Feedback().position_actual, stood) << "a faulted drive holds (brake)";
  EXPECT_EQ(drive.Feedback().velocity_actual, 0);
  // Reset and enabled again where it stands, never jumping to the old target.
  cw = jump.controlword;
  Cycles(&drive, &cw, std::nullopt, [&] { return drive.state() == State::kOperationEnabled; });
  EXPECT_EQ(drive.state(), State::kOperationEnabled);
  EXPECT_EQ(drive.Feedback().error_code, 0);
  EXPECT_EQ(drive.Feedback().position_actual, stood);
}

TEST(SimulatedCspDrive, ASilentFieldbusFaultsAnEnabledDriveWhereItIs) {
  SimulatedDriveOptions options;
  options.fieldbus_timeout_s = 0.02;
  SimulatedCspDrive drive(options);
  std::uint16_t cw = 0;
  Cycles(&drive, &cw, 0, [&] { return drive.state() == State::kOperationEnabled; });
  int cycles = 0;
  while (drive.state() == State::kOperationEnabled && cycles < 100) {
    drive.Step(kCycle);
    ++cycles;
  }
  EXPECT_EQ(drive.state(), State::kFault);
  EXPECT_EQ(drive.Feedback().error_code, kErrorFieldbus);
  EXPECT_NEAR(cycles, 20, 1) << "the fieldbus timeout, in cycles";
}

TEST(SimulatedCspDrive, ADisabledDriveNeitherFaultsOnSilenceNorMoves) {
  SimulatedCspDrive drive({}, 42);
  for (int k = 0; k < 100; ++k) drive.Step(kCycle);
  EXPECT_EQ(drive.state(), State::kSwitchOnDisabled);
  CspCommand c;
  c.controlword = ControlwordFor(Command::kShutdown);
  c.mode_of_operation = kModeCyclicSynchronousPosition;
  c.target_position = 100000;
  drive.Command(c);
  for (int k = 0; k < 10; ++k) drive.Step(kCycle);
  EXPECT_EQ(drive.Feedback().position_actual, 42);
}

TEST(SimulatedCspDrive, AnInjectedFaultIsReportedWithItsCode) {
  SimulatedCspDrive drive;
  std::uint16_t cw = 0;
  Cycles(&drive, &cw, 0, [&] { return drive.state() == State::kOperationEnabled; });
  drive.InjectFault(0x7500);
  drive.Step(kCycle);
  EXPECT_EQ(drive.state(), State::kFault);
  EXPECT_EQ(drive.Feedback().error_code, 0x7500);
}

}  // namespace
}  // namespace edsp::cia402
