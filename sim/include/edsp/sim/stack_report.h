#pragma once
// The paper's Table 1 and Figs. 6–9 from runs of the live stack: per test
// motion and PR compensation mode, the point-A error the tracker measured at
// the dwells, beside what the model predicts for the same poses
// (PointAError: commands built with the mode, the true signed PR moving the
// platform).

#include <string>
#include <vector>

#include "edsp/sim/dwell_errors.h"

namespace edsp {

struct StackTableRow {
  std::string motion;
  PrMode mode = PrMode::kNone;
  int stops = 0;
  double max_measured_m = 0.0;
  double rms_measured_m = 0.0;
  double max_predicted_m = 0.0;
};

// One row per (motion, mode), motions in first-seen order, modes ascending.
std::vector<StackTableRow> StackTable(const std::vector<DwellError>& dwells, const PlatformModel& model);

// Text shaped like the paper's Table 1: motions as rows, modes as columns,
// measured (predicted) maximum error in mm.
std::string FormatStackTable(const std::vector<StackTableRow>& rows);

// Writes <dir>/<motion>.png (error against displacement, one measured
// series and one predicted curve per mode), with the .dat files and the
// gnuplot script beside them so the figure can be restyled. Returns the PNG
// paths. Throws std::runtime_error naming the directory, or gnuplot if it is
// missing or fails.
std::vector<std::string> WriteStackPlots(const std::vector<DwellError>& dwells, const PlatformModel& model,
                                         const std::string& dir);

}  // namespace edsp
