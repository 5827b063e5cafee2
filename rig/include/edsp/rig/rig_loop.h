#pragma once
// The virtual rig on a bus and its process image: every drive cycle it takes
// the newest command from the image, steps the rig (RigCycle), writes the
// drives' feedback back, and publishes EDSP_RIG_TRUTH, EDSP_TRACKER (at the
// tracker's rate), EDSP_FAULT (the drives' watchdog, failed physics, what a
// restart found in the image) and EDSP_STATUS. edsp-rig's main only parses
// options, builds the rig and the image and runs this; tests run it on an
// in-process bus with their own clock.

#include <chrono>
#include <cstdint>
#include <functional>

#include "edsp/fault_t.hpp"
#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "edsp/rig/drive_image_server.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/transport/bus.h"

namespace edsp {

// The drives' cycle on the host's grid, 100 µs after the bridge's write
// (drives on their master's distributed clock): a setpoint reaches them
// 0.5 ms after the planner's tick, or a cycle later when the bridge wrote it
// late. A command is continued by at most 2.5 ms, where the bridge stops the
// feed-forward of a command it has not renewed (kFeedForwardLapseUs); the
// drives' watchdog holds them after --drive-watchdog-ms.
inline constexpr std::chrono::microseconds kRigPeriod{1000};
inline constexpr std::chrono::microseconds kRigPhase{500};
inline constexpr double kRigCommandHorizon_s = 2.5e-3;

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
  // One drive cycle at `now` (the wall clock at the cycle's start).
  void RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);

 private:
  VirtualRig& rig_;
  DriveImageServer& image_;
  RigCycle cycle_;
  Bus::Publisher<tracker_point_t> tracker_out_;
  Bus::Publisher<rig_truth_t> truth_out_;
  Bus::Publisher<fault_t> faults_;
  Bus::Publisher<node_status_t> status_out_;
  NodeStatus status_{"rig"};
  std::int64_t cycles_ = 0;
};

}  // namespace edsp
