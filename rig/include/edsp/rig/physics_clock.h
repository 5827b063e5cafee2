#pragma once
// The instant the rig emulator's physics describe. Real hardware's time
// passes whatever its emulator's host does, so the physics advance by whole
// cycles of their own: a wake a cycle or more late first runs the cycles it
// missed, each at its own instant, and reports them stamped so. The clock
// keeps to the earliest wakes it has seen (a wake earlier than the physics
// moves them back to it, and the physics lose that much motion once), so a
// late first wake does not offset every stamp of a run from the
// controller's grid. A wake later than the longest
// catch-up is a frozen emulator: its physics stand still over the freeze
// and continue from the wake, as a frozen rig is then seen to.

#include <cstdint>

namespace edsp {

class PhysicsClock {
 public:
  // `cycle_us` > 0; `longest_catch_up`: the most cycles a wake runs before
  // its own.
  PhysicsClock(std::int64_t cycle_us, int longest_catch_up);

  // The cycles a wake at `now` runs, its own last (≥ 1). Each runs at at()
  // and ends with Advance().
  int CyclesFor(std::int64_t now);
  std::int64_t at() const { return at_; }
  void Advance() { at_ += cycle_us_; }
  // The physics lose `cycles` cycles: the next runs that much later.
  void Lose(int cycles) { at_ += cycles * cycle_us_; }
  std::int64_t cycle_us() const { return cycle_us_; }

  // Wakes later than the longest catch-up, whose missed time was lost.
  std::int64_t freezes() const { return freezes_; }

 private:
  std::int64_t cycle_us_;
  int longest_catch_up_;
  bool started_ = false;
  std::int64_t at_ = 0;
  std::int64_t freezes_ = 0;
};

}  // namespace edsp
