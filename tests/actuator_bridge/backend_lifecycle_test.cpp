// A DriveBackend's lifecycle: the table against its specification, one
// expectation per (state, transition) pair, and the refusal's words.
#include "edsp/drive_io/backend_lifecycle.h"

#include <array>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

namespace edsp {
namespace {

using S = BackendState;
using T = BackendTransition;

constexpr std::array<S, 4> kStates{S::kUnconfigured, S::kInactive, S::kActive, S::kFault};
constexpr std::array<T, 6> kTransitions{T::kConfigure, T::kActivate, T::kDeactivate,
                                        T::kCleanup,   T::kError,    T::kRecover};

struct Expected {
  S from;
  T transition;
  bool allowed;
  S to;
};

// The specification (backend_lifecycle.h draws it), pair by pair.
constexpr Expected kSpec[] = {
    {S::kUnconfigured, T::kConfigure, true, S::kInactive},
    {S::kUnconfigured, T::kActivate, false, S::kUnconfigured},
    {S::kUnconfigured, T::kDeactivate, false, S::kUnconfigured},
    {S::kUnconfigured, T::kCleanup, false, S::kUnconfigured},
    {S::kUnconfigured, T::kError, false, S::kUnconfigured},  // no cycle runs: nothing can fail
    {S::kUnconfigured, T::kRecover, false, S::kUnconfigured},
    {S::kInactive, T::kConfigure, false, S::kInactive},  // cleanup first
    {S::kInactive, T::kActivate, true, S::kActive},
    {S::kInactive, T::kDeactivate, false, S::kInactive},
    {S::kInactive, T::kCleanup, true, S::kUnconfigured},
    {S::kInactive, T::kError, false, S::kInactive},
    {S::kInactive, T::kRecover, false, S::kInactive},  // a re-arm needs a cycling backend
    {S::kActive, T::kConfigure, false, S::kActive},
    {S::kActive, T::kActivate, false, S::kActive},
    {S::kActive, T::kDeactivate, true, S::kInactive},
    {S::kActive, T::kCleanup, false, S::kActive},  // deactivate first: the drives have power
    {S::kActive, T::kError, true, S::kFault},
    {S::kActive, T::kRecover, true, S::kActive},  // a re-arm with nothing to reset
    {S::kFault, T::kConfigure, false, S::kFault},
    {S::kFault, T::kActivate, false, S::kFault},  // only a fault reset leaves it for active
    {S::kFault, T::kDeactivate, true, S::kInactive},
    {S::kFault, T::kCleanup, false, S::kFault},
    {S::kFault, T::kError, true, S::kFault},  // failing on
    {S::kFault, T::kRecover, true, S::kActive},
};

TEST(BackendLifecycle, EveryPairOfStateAndTransitionIsAsSpecified) {
  std::set<std::pair<S, T>> checked;
  for (const Expected& e : kSpec) {
    const BackendStep step = NextBackendState(e.from, e.transition);
    SCOPED_TRACE(std::string(BackendStateName(e.from)) + " + " + BackendTransitionName(e.transition));
    EXPECT_EQ(step.allowed, e.allowed);
    EXPECT_EQ(BackendStateName(step.next), std::string(BackendStateName(e.to)));
    checked.insert({e.from, e.transition});
  }
  EXPECT_EQ(checked.size(), kStates.size() * kTransitions.size()) << "the specification misses a pair";
}

TEST(BackendLifecycle, ARefusedTransitionChangesNothingAndSaysWhatAndFromWhere) {
  BackendLifecycle lifecycle;
  std::string error;
  EXPECT_FALSE(lifecycle.Take(T::kActivate, &error));
  EXPECT_EQ(error, "cannot activate a backend that is unconfigured");
  EXPECT_EQ(lifecycle.state(), S::kUnconfigured);
  ASSERT_TRUE(lifecycle.Take(T::kConfigure, &error));
  ASSERT_TRUE(lifecycle.Take(T::kActivate, &error));
  ASSERT_TRUE(lifecycle.Take(T::kError, &error));
  EXPECT_FALSE(lifecycle.Take(T::kActivate, &error));
  EXPECT_EQ(error, "cannot activate a backend that is in fault");
  EXPECT_EQ(lifecycle.state(), S::kFault);
  EXPECT_TRUE(lifecycle.Take(T::kRecover, &error));
  EXPECT_EQ(lifecycle.state(), S::kActive);
}

}  // namespace
}  // namespace edsp
