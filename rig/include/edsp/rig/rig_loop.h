#pragma once
// The virtual rig on a bus and its process image: every drive cycle it takes
// the commands that came into the image, runs the rig's cycles (RigCycle:
// after a late wake, the missed ones too), writes the drives' newest
// feedback back, and publishes for each cycle EDSP_RIG_TRUTH, EDSP_TRACKER
// (at the tracker's rate) and EDSP_FAULT (the drives' watchdog, failed
// physics), stamped with the cycle's instant; EDSP_FAULT too for what a
// restart found in the image, and EDSP_STATUS. edsp-rig's main only parses
// options, builds the rig and the image and runs this; tests run it on an
// in-process bus with their own clock.

#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "edsp/fault_t.hpp"
#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/rig/drive_image_server.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/timing_contract.h"
#include "edsp/transport/bus.h"

namespace edsp {

// The drives' cycle on the host's grid, 100 µs after the bridge's write
// (drives on their master's distributed clock): a setpoint reaches them
// 0.5 ms after the planner's tick, or a cycle later when the bridge wrote it
// late. A command is continued by at most the feed-forward lapse, where the bridge stops the
// feed-forward of a command it has not renewed (timing_contract.h); the
// drives' watchdog holds them after --drive-watchdog-ms.
inline constexpr std::chrono::microseconds kRigPeriod{timing::kCycleUs};
inline constexpr std::chrono::microseconds kRigPhase{500};
inline constexpr double kRigCommandHorizon_s = timing::kFeedForwardLapseS;
// A wake up to 50 cycles late runs the cycles it missed (the command ring
// holds 16 of them; before those the drives take the command between, for
// gaps up to RigCycle's 50 ms, the same span). Later than that the emulator
// was frozen, and its physics stand still over the freeze, as a frozen rig
// is seen to.
inline constexpr int kRigLongestCatchUp = 50;

class RigLoop {
 public:
  // Set-up: advertises on `bus` (may throw TransportError) and reports
  // `restore` (a restarted rig's start) when it says anything. The bus, the
  // rig and the image must outlive the loop.
  RigLoop(Bus& bus, VirtualRig& rig, DriveImageServer& image, const ImageRestore& restore);
  // One rig, one cycle count, one status: no copy.
  RigLoop(const RigLoop&) = delete;
  RigLoop& operator=(const RigLoop&) = delete;

  // Until stop() is true: wait for the clock's tick, then a cycle.
  void Run(CycleClock& clock, const std::function<bool()>& stop);
  // One wake of the drive cycle at `now` (the wall clock at its start).
  void RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);

 private:
  void Publish(const RigCycleReport& report);

  VirtualRig& rig_;
  DriveImageServer& image_;
  RigCycle cycle_;
  Bus::Publisher<tracker_point_t> tracker_out_;
  Bus::Publisher<rig_truth_t> truth_out_;
  NodeReporting reporting_;
  std::int64_t cycles_ = 0;
  std::vector<DriveImageCommand> image_commands_;  // this wake's, reused
  std::vector<DriveCommand> commands_;
};

}  // namespace edsp
