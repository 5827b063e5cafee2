#include "edsp/rig/physics_clock.h"

#include <stdexcept>

namespace edsp {

PhysicsClock::PhysicsClock(std::int64_t cycle_us, int longest_catch_up)
    : cycle_us_(cycle_us), longest_catch_up_(longest_catch_up) {
  if (cycle_us <= 0) throw std::invalid_argument("PhysicsClock: the cycle must be positive");
  if (longest_catch_up < 0) throw std::invalid_argument("PhysicsClock: the longest catch-up must not be negative");
}

int PhysicsClock::CyclesFor(std::int64_t now) {
  if (!started_ || now < at_) {
    // The first wake, or one earlier than any before: the physics are at it.
    started_ = true;
    at_ = now;
    return 1;
  }
  const std::int64_t missed = (now - at_) / cycle_us_;
  if (missed > longest_catch_up_) {
    ++freezes_;
    at_ = now;
    return 1;
  }
  return static_cast<int>(missed) + 1;
}

}  // namespace edsp
