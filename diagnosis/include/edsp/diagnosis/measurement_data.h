#pragma once
// Measured data the diagnosis works on: the measurement CSV of
// interfaces.md §3 (from any source: a real tracker export included), or an
// edsp LCM log (exported to that CSV in memory). Rows keep their run, so
// hold-out splits can be by run.

#include <cstdint>
#include <string>
#include <vector>

#include "edsp/kinematics/types.h"

namespace edsp::gap {

struct MeasurementRow {
  int run = 0;  // index into MeasurementData::runs
  double time_s = 0.0;
  Vector6 pose_cmd = Vector6::Zero();   // x y z roll pitch yaw, the planner's target
  Vector6 leg_cmd_m = Vector6::Zero();  // commanded to the drives, encoder-length units
  Vector6 leg_enc_m = Vector6::Zero();  // encoder-implied; valid when has_encoder
  bool has_encoder = false;
  // The calibration's correction the controller subtracted from this
  // command (leg_corr_*_m; zero when none ran or the source does not say).
  Vector6 leg_corr_m = Vector6::Zero();
  Vector3 point_m = Vector3::Zero();  // tracker measurement of A, tracker frame
};

struct MeasurementData {
  std::vector<std::string> runs;     // in order of first appearance
  std::vector<MeasurementRow> rows;  // in file order
  std::string source;                // the file(s) it came from
  bool has_correction = false;       // the source carries leg_corr_*_m columns
  // Rows the source flagged `timing_event` = 1 (near a stall of its
  // controller: a transient no effect models), left out of `rows`.
  std::int64_t timing_excluded = 0;
  // Flagged rows kept on request (TimingEvents::kKeep), in `rows`.
  std::int64_t timing_kept = 0;
};

// Bad data error: names the file, line and column (1-based) and what is wrong.
class MeasurementError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What to do with rows flagged `timing_event` = 1: leave them out (and
// count them), or keep them like any other (to see the figure they change).
enum class TimingEvents { kLeaveOut, kKeep };

// Parses CSV text; `origin` names it in errors.
MeasurementData ParseMeasurementCsv(const std::string& text, const std::string& origin,
                                    TimingEvents timing = TimingEvents::kLeaveOut);

// A measurement CSV, or an edsp LCM log (recognised by its sync word).
MeasurementData LoadMeasurement(const std::string& path, TimingEvents timing = TimingEvents::kLeaveOut);

// Appends `more` to `data` (runs of the same name from another file get the
// file's name as a suffix, so each file's runs stay apart).
void AppendMeasurement(MeasurementData* data, MeasurementData more);

// Keeps every k-th row of each run so no run is sampled faster than
// `max_rate_hz` (consecutive 1 kHz tracker samples are nearly the same pose).
MeasurementData Decimated(const MeasurementData& data, double max_rate_hz);

}  // namespace edsp::gap
