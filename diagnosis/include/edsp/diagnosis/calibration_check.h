#pragma once
// The proof of a calibration on the rig: the same motions measured without
// and with the calibration applied by the controller, point A's error per
// motion after the best rigid alignment of each measurement (the tracker's
// frame is a nuisance), beside what the model predicted from the first.
// `edsp-gap compare`, run by `deploy/edsp calibrate`.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/diagnosis/report.h"

namespace edsp::gap {

struct MotionCheck {
  std::string run;
  RmsMax before, after;             // measured without / with the calibration
  std::optional<RmsMax> predicted;  // the model applied offline to `before`
  double shrink = 0.0;              // 1 − after/before (RMS)
};

struct CalibrationCheck {
  std::vector<MotionCheck> motions;
  MotionCheck overall;
  double noise_floor_rms_m = 0.0;  // of the calibrated measurement
  // Samples each measurement flagged timing_event (near a stall of the
  // controller), left out of both: the calibration is judged on what it can
  // change, and how much was left out is said beside it.
  std::int64_t timing_excluded_before = 0, timing_excluded_after = 0;
  double timing_share_before = 0.0, timing_share_after = 0.0;  // of each measurement's samples
  // Or, kept on request (--keep-timing-events), how many were flagged.
  std::int64_t timing_kept_before = 0, timing_kept_after = 0;
  double timing_kept_share_before = 0.0, timing_kept_share_after = 0.0;
  // The target of a calibration: RMS within 1.5× the tracker's noise floor,
  // or 90% lower than without it.
  bool target_met = false;
};

// `without`: the measurement without the calibration, evaluated with the
// saved model when `predicted` (its `after` is then the prediction) or with
// none; `with`: the calibrated measurement, evaluated with no model. Throws
// MeasurementError when the two do not hold the same runs (naming the run
// and the measurement it is missing from).
CalibrationCheck CheckCalibration(const Evaluation& without, const Evaluation& with, bool predicted);

nlohmann::json ToJson(const CalibrationCheck& check);

// A table per motion (µm), the overall row and the verdict, for a terminal.
std::string CheckTable(const CalibrationCheck& check);

// `dir`/calibration.dat and calibration.png (gnuplot): RMS and max per
// motion, before / after / predicted. Returns the PNG's path ("" if gnuplot
// could not write it).
std::string WriteCheckPlot(const CalibrationCheck& check, const std::string& dir);

}  // namespace edsp::gap
