#pragma once
// A trajectory from a CSV file: a header naming time_s, x_m, y_m, z_m,
// roll_rad, pitch_rad, yaw_rad (any order, other columns ignored, '#'
// comments allowed), one row per sample, time strictly increasing. Poses are
// interpolated linearly; sample it finely (≥ 100 Hz) for smooth motion.

#include <string>
#include <vector>

#include "edsp/planner/trajectory.h"

namespace edsp {

class CsvTrajectory final : public Trajectory {
 public:
  // Throws std::runtime_error naming the file, line and column.
  static CsvTrajectory Load(const std::string& path);
  static CsvTrajectory Parse(const std::string& text, const std::string& origin);
  double duration_s() const override { return times_.back() - times_.front(); }
  PoseSample Sample(double t_s) const override;

 private:
  std::vector<double> times_;
  std::vector<Vector6> poses_;
};

}  // namespace edsp
