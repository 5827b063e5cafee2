#pragma once
// A DriveBackend's lifecycle: ros2_control's hardware lifecycle, edsp-sized,
// its error processing a state of its own that only a fault reset leaves
// (docs/drives.md, "The backend's lifecycle").
//
//                configure               activate
//   kUnconfigured ────────▶ kInactive ────────────▶ kActive ◀─┐
//         ▲                  │  ▲  ▲                 │   │    │ recover: the operator's
//         └──── cleanup ─────┘  │  └── deactivate ───┘   │    │ re-arm reset the drives
//                               │                  error │    │ and every one is in
//                               └──── deactivate ─── kFault ──┘ operation again
//
// error: a cycle failed (the link lost, a drive out of operation). In kFault
// the backend keeps cycling (the link, the drives' watchdogs fed) but takes
// no new target: the drives hold the last one it took. Configure and
// activate that fail leave the state as it was, saying why.

#include <cstdint>
#include <string>

#include "edsp/drive_io/drive_backend.h"

namespace edsp {

enum class BackendTransition : std::uint8_t { kConfigure, kActivate, kDeactivate, kCleanup, kError, kRecover };

struct BackendStep {
  bool allowed = false;  // false: refused in this state
  BackendState next = BackendState::kUnconfigured;
};

// The whole table: every (state, transition) pair.
BackendStep NextBackendState(BackendState state, BackendTransition transition);

const char* BackendStateName(BackendState state);
const char* BackendTransitionName(BackendTransition transition);

// One backend's state, moved only through the table.
class BackendLifecycle {
 public:
  BackendState state() const { return state_; }
  // Whether `transition` may be taken from here; false with *error saying
  // "cannot <transition> a backend that is <state>".
  bool Allows(BackendTransition transition, std::string* error = nullptr) const;
  // Takes `transition` when allowed (else as Allows).
  bool Take(BackendTransition transition, std::string* error = nullptr);

 private:
  BackendState state_ = BackendState::kUnconfigured;
};

}  // namespace edsp
