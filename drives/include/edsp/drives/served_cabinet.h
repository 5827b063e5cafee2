#pragma once
// A drive cabinet as a server exposes it to its master, whatever carries the
// image (Modbus TCP, shared memory): faults injected from any thread and
// taken at the next cycle, a clock that can be stopped (a gateway whose
// drives stopped cycling), and each cycle's six feedbacks latched with the
// cycle count a master trusts (csp_image.h). CycleSchedule is the drives'
// own clock: after a late wake every missed cycle is one step.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>

#include "edsp/drives/csp_link.h"
#include "edsp/drives/drive_cabinet.h"

namespace edsp::cia402 {

class ServedCabinet {
 public:
  ServedCabinet(const SimulatedDriveOptions& options, std::unique_ptr<CspAxes> axes);

  // The master's write of all six RxPDOs, arrived at `utime`.
  void Command(const CspCommands& commands, std::int64_t utime) { cabinet_.Command(commands, utime); }
  // One drive cycle of `dt_s` (pending faults first) and its feedbacks
  // latched; false, latching nothing, while the clock is stopped.
  bool Tick(double dt_s);
  const CspFeedbacks& latched() const { return latched_; }

  // From any thread: drive `index` (0-5) raises `error_code` at its next cycle.
  void InjectFault(int index, std::uint16_t error_code);
  // From any thread: the drives stop cycling (true), or cycle again.
  void StopDrivesClock(bool stopped) { clock_stopped_.store(stopped); }

 private:
  DriveCabinet cabinet_;
  CspFeedbacks latched_{};
  std::uint16_t cycles_ = 0;  // wraps at 2^16, as the register does
  std::array<std::atomic<std::uint16_t>, kCabinetDrives> pending_faults_{};
  std::atomic<bool> clock_stopped_{false};
};

// The drives' clock. After a late wake (the simulator stopped or
// descheduled) every missed cycle is one step: the axes may be another
// process's physics that lived through the stall in real time, and
// replaying the missed cycles would command them the past (the last
// target, while the fieldbus timeout had not yet run out in the replay).
// One step sees the whole stall, as a real drive's watchdog would have.
class CycleSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  explicit CycleSchedule(double cycle_s);
  // The cycles due at `now` (0: none yet), the next tick moved past them.
  std::int64_t Due(Clock::time_point now);
  Clock::time_point next_tick() const { return next_tick_; }

 private:
  Clock::duration cycle_;
  Clock::time_point next_tick_;
};

}  // namespace edsp::cia402
