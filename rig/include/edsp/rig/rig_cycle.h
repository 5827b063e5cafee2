#pragma once
// One millisecond of the virtual rig as edsp-rig runs it (and a test or the
// in-process stack can): first what the drives and the instruments report
// at the cycle's start, which is the state the previous cycle's physics
// reached, then the drives take the newest command and the physics advance
// one cycle. A report stamped t thus describes the platform at t, as the
// offline stack's (StackSimulation) does; and a command taken a little after
// the instant it is for continues from that instant (AtCycleStart). A wake
// of edsp-rig's loop runs the cycles its physics clock says (PhysicsClock):
// after a late wake, the ones it missed too.

#include <cstdint>
#include <vector>

#include "edsp/rig/physics_clock.h"
#include "edsp/rig/virtual_rig.h"

namespace edsp {

struct RigCycleReport {
  std::int64_t utime = 0;    // the instant it describes: `now`
  DriveFeedback feedback;    // the drives at `now`
  rig_truth_t truth{};       // the platform at `now`
  bool tracker_due = false;  // the tracker's rate decides
  tracker_point_t tracker{};
  bool watchdog_changed = false;  // the drives started or stopped holding,
  bool watchdog_tripped = false;  //   which, at the cycle's command
  double since_command_s = 0.0;   //   and how long since the last
  bool physics_failed = false;    // no platform pose fits the drives after this cycle
};

// A drive command taken at `now`, later than the instant it is for
// (command.utime): the target continued along its velocity feed-forward to
// `now`, by at most `horizon_s` (edsp-rig: 2.5 ms, the bridge's feed-forward lapse). The
// drives then follow the setpoints' clock whatever the phase between the
// bridge's cycle and theirs, as drives synchronised to the master's clock
// do. A command without a stamp (utime 0) is taken as it is.
DriveSetpoint AtCycleStart(const DriveSetpoint& command, std::int64_t now, double horizon_s);

// The drives' command at `at` between two the controller sent, `from`
// before it and `to` after (stamped; from.utime < to.utime): the parabola
// that leaves `from` along its velocity feed-forward and reaches `to`'s
// angles, with its slope as the feed-forward. Only `from`'s feed-forward is
// used: the one after a stall may be a rejoin's, taken over a whole cycle.
DriveSetpoint CommandBetween(const DriveSetpoint& from, const DriveSetpoint& to, std::int64_t at);

// A command from the drives' process image: the setpoint and whether it
// enables the drives.
struct DriveCommand {
  DriveSetpoint setpoint;
  bool enable = false;
};

class RigCycle {
 public:
  // `horizon_s`: how late a command may be continued (AtCycleStart);
  // `longest_catch_up`: the most cycles a late wake runs before its own.
  explicit RigCycle(VirtualRig* rig, double cycle_s = 1e-3, double horizon_s = 1e-3, int longest_catch_up = 50);

  // One wake of the loop at `now` (the wall clock): the cycles the physics
  // clock gives it, the missed ones first, each reported at its own instant
  // (the last at about `now`). `commands`: those that arrived since the last
  // wake, in order. A missed cycle takes the newest command stamped at or
  // before its instant, as the drives took it on time; the wake's own cycle
  // takes the newest of all. Stamps by another host's clock (or none) cannot
  // say which missed cycle had which command: then the missed time is lost,
  // one cycle runs, and it takes the newest.
  //
  // When the whole host pauses, the controller stalls with the emulator,
  // which a real rig's would not have done; the drives would have had their
  // commands. So a late wake whose controller was on time before and has not
  // caught up yet (its newest command is older than the tick before the
  // wake's own cycle) waits for it, up to 5 ms (no reports: empty), and a
  // missed cycle with no command of its own, between the last taken and a
  // later one at most 50 ms after it, takes the command between
  // (CommandBetween) instead of braking into a transient only this host's
  // pause caused. For the same reason a missed cycle passes over a command
  // that re-writes a setpoint already taken (the bridge drops the
  // feed-forward of a command it has not renewed for 2.5 ms, under the old
  // stamp). A controller that stalls alone still stalls the drives: the
  // emulator was on time. The reports live until the next wake.
  const std::vector<RigCycleReport>& Wake(std::int64_t now, const std::vector<DriveCommand>& commands);

  // `now`: the wall clock at the cycle's start; `command`: the newest drive
  // command since the last cycle, or null when none came. A command equal to
  // the last one taken (stamp, targets, feed-forward, enable) only keeps the
  // drives' watchdog quiet (VirtualRig::KeepAlive).
  RigCycleReport Step(std::int64_t now, const DriveSetpoint* command, bool enable);

 private:
  void Take(std::int64_t now, const DriveSetpoint& command, bool enable);
  // Whether a missed cycle at `at` takes the command between the last taken
  // and `after`, the next that came.
  bool Bridges(const DriveCommand& after, std::int64_t at) const;
  // Whether `c` re-writes a setpoint already taken (its stamp or older).
  bool Rewritten(const DriveCommand& c) const;
  // Whether the commands' stamps are on the physics clock: the last cycle
  // took one for about its instant (not another host's clock, nor a
  // controller that had stopped). Only then do they say which missed cycle
  // had which, and is a controller late after a pause waited for.
  bool StampsOnThisClock() const;
  // Whether a wake `cycles` long waits for the controller to catch up.
  bool AwaitsTheController(std::int64_t now, int cycles);
  // The wake's own cycle: the newest command of all.
  RigCycleReport OwnCycle(std::int64_t at, std::size_t* next);
  // A missed cycle: the newest command stamped at or before `at` (a disable
  // never passed over), or the one between the last taken and the next.
  RigCycleReport MissedCycle(std::int64_t at, std::size_t* next);

  static constexpr std::int64_t kLongestBridgedGapUs = 50'000;
  static constexpr std::int64_t kLongestWaitUs = 5'000;

  VirtualRig* rig_;
  double cycle_s_;
  double horizon_s_;
  PhysicsClock clock_;
  std::vector<RigCycleReport> reports_;
  std::vector<DriveCommand> pending_;  // came, not taken yet (a wake that waited)
  std::int64_t waiting_since_ = 0;     // the first wake that waited; 0: none waits
  bool watchdog_reported_ = false;
  bool taken_any_ = false;
  DriveSetpoint last_taken_;
  bool last_enable_ = false;
};

}  // namespace edsp
