#include "edsp/actuator_bridge/bridge_state.h"

namespace edsp {

namespace {

constexpr BridgeTransition To(BridgeState next) { return {true, next}; }
constexpr BridgeTransition kRefused{};

BridgeTransition OnCommandAccepted(BridgeState state) {
  switch (state) {
    case BridgeState::kStartupHold:
    case BridgeState::kFollowing: return To(BridgeState::kFollowing);
    case BridgeState::kArmed:
    case BridgeState::kRejoining: return To(BridgeState::kRejoining);
    case BridgeState::kLatched: return kRefused;  // latched: nothing moves the legs but a re-arm
  }
  return kRefused;
}

BridgeTransition OnStaleOrDrivesLost(BridgeState state, BridgeEvent event) {
  switch (state) {
    case BridgeState::kFollowing:
    case BridgeState::kRejoining: return To(BridgeState::kLatched);
    // Re-armed after a latch: the drives' outage makes the stream's next
    // command as unverifiable as it was. (A stale limit does not run while
    // holding: a re-armed bridge waits for its stream.)
    case BridgeState::kArmed:
      return event == BridgeEvent::kDrivesLost ? To(BridgeState::kLatched) : To(BridgeState::kArmed);
    case BridgeState::kStartupHold: return To(BridgeState::kStartupHold);
    case BridgeState::kLatched: return To(BridgeState::kLatched);
  }
  return kRefused;
}

BridgeTransition OnRearm(BridgeState state) {
  switch (state) {
    case BridgeState::kStartupHold:  // a restarted bridge started into a stream elsewhere
    case BridgeState::kLatched:
    case BridgeState::kArmed: return To(BridgeState::kArmed);
    case BridgeState::kFollowing:
    case BridgeState::kRejoining: return To(state);  // nothing to re-arm
  }
  return kRefused;
}

}  // namespace

BridgeTransition NextBridgeState(BridgeState state, BridgeEvent event) {
  switch (event) {
    case BridgeEvent::kCommandAccepted: return OnCommandAccepted(state);
    case BridgeEvent::kCaughtUp: return state == BridgeState::kRejoining ? To(BridgeState::kFollowing) : kRefused;
    case BridgeEvent::kStale:
    case BridgeEvent::kDrivesLost: return OnStaleOrDrivesLost(state, event);
    case BridgeEvent::kRearm: return OnRearm(state);
    // A moving bridge catches a stream that went on without its drives at the
    // rejoin speed, as after a re-arm, rather than by a step (no latch: every
    // command stayed valid).
    case BridgeEvent::kStreamAhead:
      return state == BridgeState::kFollowing || state == BridgeState::kRejoining ? To(BridgeState::kRejoining)
                                                                                  : kRefused;
  }
  return kRefused;
}

bool IsHolding(BridgeState state) {
  return state == BridgeState::kStartupHold || state == BridgeState::kLatched || state == BridgeState::kArmed;
}

bool IsRejoining(BridgeState state) { return state == BridgeState::kArmed || state == BridgeState::kRejoining; }

const char* BridgeStateName(BridgeState state) {
  switch (state) {
    case BridgeState::kStartupHold: return "startup-hold";
    case BridgeState::kFollowing: return "following";
    case BridgeState::kLatched: return "latched";
    case BridgeState::kArmed: return "armed";
    case BridgeState::kRejoining: return "rejoining";
  }
  return "?";
}

const char* BridgeEventName(BridgeEvent event) {
  switch (event) {
    case BridgeEvent::kCommandAccepted: return "command accepted";
    case BridgeEvent::kCaughtUp: return "caught up";
    case BridgeEvent::kStale: return "stale";
    case BridgeEvent::kDrivesLost: return "drives lost";
    case BridgeEvent::kRearm: return "re-arm";
    case BridgeEvent::kStreamAhead: return "stream ahead";
  }
  return "?";
}

}  // namespace edsp
