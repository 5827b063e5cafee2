#pragma once
// One millisecond of the virtual rig as edsp-rig runs it (and a test or the
// in-process stack can): first what the drives and the instruments report
// at the cycle's start, which is the state the previous cycle's physics
// reached, then the drives take the newest command and the physics advance
// one cycle. A report stamped t thus describes the platform at t, as the
// offline stack's (StackSimulation) does; and a command taken a little after
// the instant it is for continues from that instant (AtCycleStart).

#include <cstdint>

#include "edsp/rig/virtual_rig.h"

namespace edsp {

struct RigCycleReport {
  DriveFeedback feedback;    // the drives at `now`
  rig_truth_t truth{};       // the platform at `now`
  bool tracker_due = false;  // the tracker's rate decides
  tracker_point_t tracker{};
  bool watchdog_changed = false;  // the drives started or stopped holding (rig.watchdog_tripped() says which)
  bool physics_failed = false;    // no platform pose fits the drives after this cycle
};

// A drive command taken at `now`, later than the instant it is for
// (command.utime): the target continued along its velocity feed-forward to
// `now`, by at most `horizon_s` (edsp-rig: 2.5 ms, the bridge's feed-forward lapse). The
// drives then follow the setpoints' clock whatever the phase between the
// bridge's cycle and theirs, as drives synchronised to the master's clock
// do. A command without a stamp (utime 0) is taken as it is.
DriveSetpoint AtCycleStart(const DriveSetpoint& command, std::int64_t now, double horizon_s);

class RigCycle {
 public:
  // `horizon_s`: how late a command may be continued (AtCycleStart).
  explicit RigCycle(VirtualRig* rig, double cycle_s = 1e-3, double horizon_s = 1e-3)
      : rig_(rig), cycle_s_(cycle_s), horizon_s_(horizon_s) {}

  // `now`: the wall clock at the cycle's start; `command`: the newest drive
  // command since the last cycle, or null when none came. A command equal to
  // the last one taken (stamp, targets, feed-forward, enable) only keeps the
  // drives' watchdog quiet (VirtualRig::KeepAlive).
  RigCycleReport Step(std::int64_t now, const DriveSetpoint* command, bool enable);

 private:
  void Take(std::int64_t now, const DriveSetpoint& command, bool enable);

  VirtualRig* rig_;
  double cycle_s_;
  double horizon_s_;
  bool watchdog_reported_ = false;
  bool taken_any_ = false;
  DriveSetpoint last_taken_;
  bool last_enable_ = false;
};

}  // namespace edsp
