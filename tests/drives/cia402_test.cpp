// The CiA 402 state machine against the standard's own table, written out
// here row by row (IEC 61800-7-201, device control): every transition a
// controlword causes, every one it must not, the statusword of each state,
// and a master that enables a drive from any state by its statusword alone.
#include <gtest/gtest.h>

#include <vector>

#include "edsp/drives/cia402.h"

namespace edsp::cia402 {
namespace {

const std::vector<State> kStates = {
    State::kNotReadyToSwitchOn, State::kSwitchOnDisabled, State::kReadyToSwitchOn,     State::kSwitchedOn,
    State::kOperationEnabled,   State::kQuickStopActive,  State::kFaultReactionActive, State::kFault};

// Brings a fresh drive into `state` by the standard's own paths.
DriveStateMachine DriveIn(State state) {
  DriveStateMachine d;
  auto to_operation = [&d] {
    d.OnControlword(0x06);
    d.OnControlword(0x07);
    d.OnControlword(0x0F);
  };
  switch (state) {
    case State::kSwitchOnDisabled: break;
    case State::kReadyToSwitchOn: d.OnControlword(0x06); break;
    case State::kSwitchedOn:
      d.OnControlword(0x06);
      d.OnControlword(0x07);
      break;
    case State::kOperationEnabled: to_operation(); break;
    case State::kQuickStopActive:
      to_operation();
      d.OnControlword(0x02);
      break;
    case State::kFaultReactionActive:
      to_operation();
      d.RaiseFault(0x8611);
      break;
    case State::kFault:
      to_operation();
      d.RaiseFault(0x8611);
      d.FaultReactionDone();
      break;
    case State::kNotReadyToSwitchOn: break;  // never reached from outside: power-up only
  }
  EXPECT_EQ(d.state(), state == State::kNotReadyToSwitchOn ? State::kSwitchOnDisabled : state);
  return d;
}

struct Row {
  State from;
  std::uint16_t controlword;
  State to;
  int transition;
};

// The standard's table: command bits (7, 3-0) → transition. Bits the table
// marks "x" are given both ways where it matters (quick stop 0x02/0x03/0x0B,
// disable voltage 0x00/0x01/0x04/0x0D, shutdown 0x06/0x0E).
const std::vector<Row> kTable = {
    {State::kSwitchOnDisabled, 0x06, State::kReadyToSwitchOn, 2},
    {State::kSwitchOnDisabled, 0x0E, State::kReadyToSwitchOn, 2},
    {State::kReadyToSwitchOn, 0x07, State::kSwitchedOn, 3},
    {State::kReadyToSwitchOn, 0x0F, State::kSwitchedOn, 3},
    {State::kSwitchedOn, 0x0F, State::kOperationEnabled, 4},
    {State::kOperationEnabled, 0x07, State::kSwitchedOn, 5},
    {State::kSwitchedOn, 0x06, State::kReadyToSwitchOn, 6},
    {State::kSwitchedOn, 0x0E, State::kReadyToSwitchOn, 6},
    {State::kReadyToSwitchOn, 0x00, State::kSwitchOnDisabled, 7},
    {State::kReadyToSwitchOn, 0x02, State::kSwitchOnDisabled, 7},
    {State::kReadyToSwitchOn, 0x0D, State::kSwitchOnDisabled, 7},
    {State::kOperationEnabled, 0x06, State::kReadyToSwitchOn, 8},
    {State::kOperationEnabled, 0x0E, State::kReadyToSwitchOn, 8},
    {State::kOperationEnabled, 0x00, State::kSwitchOnDisabled, 9},
    {State::kOperationEnabled, 0x0D, State::kSwitchOnDisabled, 9},
    {State::kSwitchedOn, 0x00, State::kSwitchOnDisabled, 10},
    {State::kSwitchedOn, 0x01, State::kSwitchOnDisabled, 10},
    {State::kSwitchedOn, 0x02, State::kSwitchOnDisabled, 10},
    {State::kSwitchedOn, 0x03, State::kSwitchOnDisabled, 10},
    {State::kOperationEnabled, 0x02, State::kQuickStopActive, 11},
    {State::kOperationEnabled, 0x03, State::kQuickStopActive, 11},
    {State::kOperationEnabled, 0x0B, State::kQuickStopActive, 11},
    {State::kQuickStopActive, 0x00, State::kSwitchOnDisabled, 12},
    {State::kQuickStopActive, 0x04, State::kSwitchOnDisabled, 12},
    {State::kFault, 0x80, State::kSwitchOnDisabled, 15},
    {State::kFault, 0x86, State::kSwitchOnDisabled, 15},
    {State::kQuickStopActive, 0x0F, State::kOperationEnabled, 16},
};

TEST(Cia402, EveryTransitionOfTheStandardsTable) {
  for (const Row& row : kTable) {
    DriveStateMachine d = DriveIn(row.from);
    EXPECT_EQ(d.OnControlword(row.controlword), row.transition)
        << StateName(row.from) << " + 0x" << std::hex << row.controlword;
    EXPECT_EQ(d.state(), row.to) << StateName(row.from) << " + 0x" << std::hex << row.controlword;
  }
}

// The standard's command table as masks over bits 7 and 3-0 (a word
// matching none is no command), and its transitions per (state, command):
// a second formulation, checked against the drive for all 32 words in
// every state.
struct CommandBits {
  Command command;
  std::uint16_t mask, value;
};
const std::vector<CommandBits> kCommandBits = {
    {Command::kShutdown, 0x87, 0x06},       {Command::kSwitchOn, 0x8F, 0x07},  {Command::kEnableOperation, 0x8F, 0x0F},
    {Command::kDisableVoltage, 0x82, 0x00}, {Command::kQuickStop, 0x86, 0x02},
};
struct Edge {
  State from;
  Command command;
  State to;
  int transition;
};
const std::vector<Edge> kEdges = {
    {State::kSwitchOnDisabled, Command::kShutdown, State::kReadyToSwitchOn, 2},
    {State::kReadyToSwitchOn, Command::kSwitchOn, State::kSwitchedOn, 3},
    {State::kReadyToSwitchOn, Command::kEnableOperation, State::kSwitchedOn, 3},
    {State::kSwitchedOn, Command::kEnableOperation, State::kOperationEnabled, 4},
    {State::kOperationEnabled, Command::kSwitchOn, State::kSwitchedOn, 5},  // disable operation
    {State::kSwitchedOn, Command::kShutdown, State::kReadyToSwitchOn, 6},
    {State::kReadyToSwitchOn, Command::kDisableVoltage, State::kSwitchOnDisabled, 7},
    {State::kReadyToSwitchOn, Command::kQuickStop, State::kSwitchOnDisabled, 7},
    {State::kOperationEnabled, Command::kShutdown, State::kReadyToSwitchOn, 8},
    {State::kOperationEnabled, Command::kDisableVoltage, State::kSwitchOnDisabled, 9},
    {State::kSwitchedOn, Command::kDisableVoltage, State::kSwitchOnDisabled, 10},
    {State::kSwitchedOn, Command::kQuickStop, State::kSwitchOnDisabled, 10},
    {State::kOperationEnabled, Command::kQuickStop, State::kQuickStopActive, 11},
    {State::kQuickStopActive, Command::kDisableVoltage, State::kSwitchOnDisabled, 12},
    {State::kQuickStopActive, Command::kEnableOperation, State::kOperationEnabled, 16},
};

TEST(Cia402, EveryControlwordInEveryStateAsTheStandardsMasksSay) {
  int refused = 0;
  for (State from : kStates) {
    if (from == State::kNotReadyToSwitchOn) continue;
    for (std::uint16_t word = 0; word < 0x100; ++word) {
      if ((word & 0x70) != 0) continue;  // bits 4-6: mode-specific, not device control
      int matches = 0;
      Edge expected{from, Command::kFaultReset, from, 0};
      for (const CommandBits& bits : kCommandBits) {
        if ((word & bits.mask) != bits.value) continue;
        ++matches;
        for (const Edge& edge : kEdges) {
          if (edge.from == from && edge.command == bits.command) expected = edge;
        }
      }
      if (from == State::kFault && (word & 0x80) != 0)
        expected = {from, Command::kFaultReset, State::kSwitchOnDisabled, 15};
      EXPECT_LE(matches, 1) << "the masks overlap at 0x" << std::hex << word;
      DriveStateMachine d = DriveIn(from);
      EXPECT_EQ(d.OnControlword(word), expected.transition) << StateName(from) << " + 0x" << std::hex << word;
      EXPECT_EQ(d.state(), expected.to) << StateName(from) << " + 0x" << std::hex << word;
      if (expected.transition == 0) ++refused;
    }
  }
  EXPECT_GT(refused, 100);  // most words change nothing in most states
}

TEST(Cia402, NoControlwordLeavesAFaultReactionOrAFaultWithoutAResetEdge) {
  for (std::uint16_t word = 0; word < 0x80; ++word) {
    DriveStateMachine reacting = DriveIn(State::kFaultReactionActive);
    EXPECT_EQ(reacting.OnControlword(word), 0);
    EXPECT_EQ(reacting.state(), State::kFaultReactionActive);
    DriveStateMachine faulted = DriveIn(State::kFault);
    EXPECT_EQ(faulted.OnControlword(word), 0);
    EXPECT_EQ(faulted.state(), State::kFault);
  }
}

TEST(Cia402, AFaultResetActsOnTheRisingEdgeOfBit7Only) {
  DriveStateMachine d = DriveIn(State::kOperationEnabled);
  d.OnControlword(0x80);  // bit 7 already high when the fault comes
  d.RaiseFault(0x7500);
  d.FaultReactionDone();
  EXPECT_EQ(d.error_code(), 0x7500);
  EXPECT_EQ(d.OnControlword(0x80), 0) << "a bit held high is no edge";
  EXPECT_EQ(d.state(), State::kFault);
  EXPECT_EQ(d.OnControlword(0x00), 0);
  EXPECT_EQ(d.OnControlword(0x80), 15);
  EXPECT_EQ(d.state(), State::kSwitchOnDisabled);
  EXPECT_EQ(d.error_code(), 0) << "the reset clears 603Fh";
}

TEST(Cia402, AFaultFromAnyPoweredStateRunsItsReactionFirst) {
  for (State from : {State::kSwitchOnDisabled, State::kReadyToSwitchOn, State::kSwitchedOn, State::kOperationEnabled,
                     State::kQuickStopActive}) {
    DriveStateMachine d = DriveIn(from);
    d.RaiseFault(0x8611);  // following error
    EXPECT_EQ(d.state(), State::kFaultReactionActive) << StateName(from);
    EXPECT_FALSE(d.FollowsTarget());
    d.RaiseFault(0x2310);  // a second fault during the reaction keeps the first code
    d.FaultReactionDone();
    EXPECT_EQ(d.state(), State::kFault);
    EXPECT_EQ(d.error_code(), 0x8611);
  }
}

TEST(Cia402, AQuickStopThatHasStoppedEndsSwitchOnDisabled) {
  DriveStateMachine d = DriveIn(State::kQuickStopActive);
  EXPECT_FALSE(d.FollowsTarget());
  d.QuickStopDone();
  EXPECT_EQ(d.state(), State::kSwitchOnDisabled);
}

TEST(Cia402, OnlyOperationEnabledFollowsTheTarget) {
  for (State s : kStates) {
    if (s == State::kNotReadyToSwitchOn) continue;
    EXPECT_EQ(DriveIn(s).FollowsTarget(), s == State::kOperationEnabled) << StateName(s);
  }
}

TEST(Cia402, EveryStatuswordReadsBackAsItsState) {
  for (State s : kStates) {
    EXPECT_EQ(StateOfStatusword(StatusBits(s)), s) << StateName(s);
    // Bits outside the state's mask (warning, remote, target reached,
    // following error, manufacturer bits) do not change what it reads as.
    const std::uint16_t noisy =
        StatusBits(s) | kStatusWarning | kStatusRemote | kStatusTargetReached | kStatusFollowingError | 0x8000;
    EXPECT_EQ(StateOfStatusword(noisy), s) << StateName(s);
  }
  // The standard's examples (low byte): 0x40 disabled, 0x21 ready,
  // 0x23 switched on, 0x27 enabled, 0x07 quick stop, 0x0F reaction, 0x08 fault.
  EXPECT_EQ(StateOfStatusword(0x0250), State::kSwitchOnDisabled);
  EXPECT_EQ(StateOfStatusword(0x0231), State::kReadyToSwitchOn);
  EXPECT_EQ(StateOfStatusword(0x0233), State::kSwitchedOn);
  EXPECT_EQ(StateOfStatusword(0x0237), State::kOperationEnabled);
  EXPECT_EQ(StateOfStatusword(0x0217), State::kQuickStopActive);
  EXPECT_EQ(StateOfStatusword(0x021F), State::kFaultReactionActive);
  EXPECT_EQ(StateOfStatusword(0x0218), State::kFault);
}

TEST(Cia402, AMasterReadingOnlyStatuswordsEnablesADriveFromAnyState) {
  for (State from : kStates) {
    if (from == State::kNotReadyToSwitchOn) continue;
    DriveStateMachine d = DriveIn(from);
    std::uint16_t controlword = 0x0000;
    int cycles = 0;
    for (; cycles < 10 && !d.FollowsTarget(); ++cycles) {
      if (d.state() == State::kFaultReactionActive) d.FaultReactionDone();  // the drive's own braking ends
      if (d.state() == State::kQuickStopActive && cycles > 0) d.QuickStopDone();
      controlword = ControlwordTowardOperation(StateOfStatusword(d.statusword()), controlword);
      d.OnControlword(controlword);
    }
    EXPECT_TRUE(d.FollowsTarget()) << "from " << StateName(from) << ": " << StateName(d.state());
    EXPECT_LE(cycles, 6) << "from " << StateName(from);
  }
}

TEST(Cia402, TheMasterNeverResumesOutOfAStopTheDriveIsCarryingOut) {
  for (State s : {State::kQuickStopActive, State::kFaultReactionActive}) {
    const std::uint16_t word = ControlwordTowardOperation(s, 0x0F);
    DriveStateMachine d = DriveIn(s);
    d.OnControlword(word);
    EXPECT_FALSE(d.FollowsTarget()) << StateName(s);
  }
}

}  // namespace
}  // namespace edsp::cia402
