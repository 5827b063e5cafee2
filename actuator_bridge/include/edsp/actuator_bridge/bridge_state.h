#pragma once
// The actuator bridge's safety state: one explicit state machine. What may
// move the legs, and what it takes to move them again after a fault, is
// decided here and nowhere else (docs/stack.md, "The bridge's states").
//
//                  command within one step
//   kStartupHold ─────────────────────────▶ kFollowing ◀──────────────┐
//        │                                    │                      │ caught up
//        │ re-arm               stale, drives lost                   │
//        ▼                                    ▼                      │
//     kArmed ◀─────────── re-arm ───────── kLatched ◀── stale, ── kRejoining
//      │  └──────────── drives lost ──────────▲       drives lost    ▲
//      └──────────────── command (from anywhere) ────────────────────┘
//   following ── stream ahead (after a silence, more than a cycle away) ──▶ rejoining
//
// Drive health is an input, not a state: while the drives do not answer,
// every command is refused in every state; losing them latches a bridge that
// had a stream (an outage at start-up only delays the start).

#include <cstdint>

namespace edsp {

enum class BridgeState : std::uint8_t {
  kStartupHold,  // holding where the drives were found; no stream accepted yet
  kFollowing,    // the stream's commands go to the drives
  kLatched,      // held after stale input or a drive outage: only a re-arm leaves
  kArmed,        // re-armed, holding: the next valid command starts the stream from anywhere
  kRejoining,    // on the way to the stream at the rejoin speed
};

enum class BridgeEvent : std::uint8_t {
  kCommandAccepted,  // a valid command became the target
  kCaughtUp,         // the rejoining legs reached the stream
  kStale,            // no valid command for the stale limit (or this process starved as long)
  kDrivesLost,       // the drives stopped answering or left operation
  kRearm,            // an operator's EDSP_ARM (drives already reset)
  kStreamAhead,      // the stream came back farther from the drives than they go in a cycle
};

struct BridgeTransition {
  bool allowed = false;  // false: the event cannot happen in this state (a refusal or a bug)
  BridgeState next = BridgeState::kStartupHold;
};

// The whole table: every (state, event) pair.
BridgeTransition NextBridgeState(BridgeState state, BridgeEvent event);

// The legs are held (not following a stream) in this state.
bool IsHolding(BridgeState state);
// Commands continue from the last command, not from the target (rejoining).
bool IsRejoining(BridgeState state);

const char* BridgeStateName(BridgeState state);
const char* BridgeEventName(BridgeEvent event);

}  // namespace edsp
