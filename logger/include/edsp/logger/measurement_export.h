#pragma once
// The measurement CSV of interfaces.md §3 from an edsp log: one row per valid
// tracker sample (the platform at its stamp), with what the controller
// commanded for that instant: the last setpoint stamped at or before it, the
// leg command answering that setpoint (leg_command_t.setpoint_utime), the
// last encoder reading stamped at or before it; the pose carried along the
// setpoint's velocity, and the legs between that command and the next, to
// the sample's instant (a live tracker samples up to a cycle after the
// setpoint; offline the two coincide and nothing moves). Paired by the
// messages' own stamps, not by their order of arrival at the logger, which
// interleaves the processes by a cycle or more (up to 0.5 s late is paired).
// `run` is the motion the setpoint belongs to (its trajectory name up to the
// first '/'), so hold-out splits can be by run. `leg_corr_*_m` is the
// calibration's correction the kinematics took off that command (its own
// fields: IK − PR − command; zero without a calibration). `timing_event` is 1 for a
// sample near a stall of the real-time system (stall_watch.h: the drives
// more than 10 ms without a new command, EDSP_LEG_STATE's command_seq, or
// 2.5 ms without a reading; the rig emulator's cycles 1.5 cycles apart),
// until the drives have recovered: a transient no calibration can model
// (docs/calibration.md).

#include <cstdint>
#include <ostream>
#include <string>

namespace edsp {

struct MeasurementExport {
  std::int64_t rows = 0;
  std::int64_t skipped = 0;        // tracker samples invalid or before any command
  std::int64_t timing_events = 0;  // rows flagged timing_event (near a stall of the controller)
  bool damaged = false;            // the log ended in damage; rows before it are written
  std::int64_t damage_offset = -1;
};

// Throws std::runtime_error if the log cannot be opened.
MeasurementExport ExportMeasurementCsv(const std::string& log_path, std::ostream& out);

}  // namespace edsp
