#pragma once
// The stalls of the real-time system in a log, found as its messages come,
// and whether a tracker sample lies near one (the measurement export's
// `timing_event`). A stall: longer than 2.5 ms between two readings of the
// drives (the bridge itself late), longer than 10 ms without a new command
// for them (the bridge rides through shorter silences on the platform's
// path), or two cycles of the rig emulator further apart than 1.5 cycles
// (its physics lost the time between). A sample is near one from 2 ms
// before it until the drives show they have recovered: the stall over, at
// least 10 ms more for the servo, then the drives' tracking error (command
// − encoder, at the reading's instant) back under twice what it was before
// the stall (at least 20 µm) for 20 ms; at most 100 ms + 10 ms per ms
// stalled (at most 1 s more), beyond the longest catch-up measured live
// (docs/figures.md, "The stack"). A stall still open when a sample is written flags it too. Stamps are the
// senders' word: the arithmetic is in double.

#include <cstdint>
#include <deque>
#include <optional>

namespace edsp {

class StallWatch {
 public:
  // A leg state: the drives' reading at `utime`, running command `seq`
  // (0: none yet). Older than the newest (reordered, repeated): ignored.
  void Reading(std::int64_t utime, std::int64_t seq);
  // A cycle of the rig emulator at `utime`.
  void RigCycle(std::int64_t utime);
  // Any other instant the log vouches for (a tracker sample's): readings
  // that stopped before it stopped for good, so far.
  void Heard(std::int64_t utime);
  // Samples come in order of their stamps, each with the drives' tracking
  // error at the latest reading before it (largest leg, m; none: unknown).
  bool Near(std::int64_t utime, std::optional<double> tracking_error_m);

 private:
  struct Stall {
    double from, to;
    double threshold_m = -1.0;  // the tracking error that is normal again (< 0: not known yet)
    double normal_since = 0.0;  // the first of the samples since, all back under it
    bool recovered = false;
  };
  struct Tracking {
    double utime, error_m;
  };
  void Gap(std::int64_t from, std::int64_t to, double longest_us);
  bool StillNear(Stall* stall, double t, std::optional<double> error_m) const;
  double NormalBefore(double from) const;  // the largest tracking error in the 50 ms before `from`

  std::deque<Stall> stalls_;
  std::deque<Tracking> recent_;  // the samples' tracking errors, the last 50 ms and more
  std::int64_t newest_reading_ = 0, command_seq_ = 0, command_since_ = 0, newest_cycle_ = 0, newest_heard_ = 0;
};

}  // namespace edsp
