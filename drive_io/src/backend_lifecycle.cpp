#include "edsp/drive_io/backend_lifecycle.h"

namespace edsp {

BackendStep NextBackendState(BackendState state, BackendTransition transition) {
  using S = BackendState;
  using T = BackendTransition;
  switch (state) {
    case S::kUnconfigured:
      if (transition == T::kConfigure) return {true, S::kInactive};
      break;
    case S::kInactive:
      if (transition == T::kActivate) return {true, S::kActive};
      if (transition == T::kCleanup) return {true, S::kUnconfigured};
      break;
    case S::kActive:
      if (transition == T::kDeactivate) return {true, S::kInactive};
      if (transition == T::kError) return {true, S::kFault};
      if (transition == T::kRecover) return {true, S::kActive};  // a re-arm with nothing to reset
      break;
    case S::kFault:
      if (transition == T::kDeactivate) return {true, S::kInactive};
      if (transition == T::kError) return {true, S::kFault};  // failing on
      if (transition == T::kRecover) return {true, S::kActive};
      break;
  }
  return {false, state};
}

const char* BackendStateName(BackendState state) {
  switch (state) {
    case BackendState::kUnconfigured: return "unconfigured";
    case BackendState::kInactive: return "inactive";
    case BackendState::kActive: return "active";
    case BackendState::kFault: return "in fault";
  }
  return "?";
}

const char* BackendTransitionName(BackendTransition transition) {
  switch (transition) {
    case BackendTransition::kConfigure: return "configure";
    case BackendTransition::kActivate: return "activate";
    case BackendTransition::kDeactivate: return "deactivate";
    case BackendTransition::kCleanup: return "clean up";
    case BackendTransition::kError: return "fault";
    case BackendTransition::kRecover: return "recover";
  }
  return "?";
}

bool BackendLifecycle::Allows(BackendTransition transition, std::string* error) const {
  if (NextBackendState(state_, transition).allowed) return true;
  if (error != nullptr) {
    *error =
        std::string("cannot ") + BackendTransitionName(transition) + " a backend that is " + BackendStateName(state_);
  }
  return false;
}

bool BackendLifecycle::Take(BackendTransition transition, std::string* error) {
  if (!Allows(transition, error)) return false;
  state_ = NextBackendState(state_, transition).next;
  return true;
}

}  // namespace edsp
