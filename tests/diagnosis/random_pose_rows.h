#pragma once
// Measurement rows at random poses about home, for tests of the design.

#include <random>

#include "edsp/diagnosis/measurement_data.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::gap {

// `rows` rows in three runs, `spacing_s` apart, at poses within ±`span`
// (m, rad) of home, commanded with `compensation`; A measured exactly where
// `moved(pose, A)` puts it, seen in the tracker frame X_TB.
template <typename Moved>
MeasurementData RandomPoseRows(const PlatformModel& model, const Pose& X_TB, int rows, PrMode compensation, double span,
                               double spacing_s, unsigned seed, Moved moved) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MeasurementData d;
  d.runs = {"a", "b", "c"};
  d.source = "synthetic";
  const Matrix3 R = RotationFromRpy(X_TB.rpy_rad);
  for (int k = 0; k < rows; ++k) {
    MeasurementRow row;
    row.run = k * 3 / rows;
    row.time_s = spacing_s * k;
    row.pose_cmd = model.home_pose().ToVector();
    row.pose_cmd.head<3>() += span * Vector3(u(rng), u(rng), u(rng));
    row.pose_cmd.tail<3>() += span * Vector3(u(rng), u(rng), u(rng));
    const Pose pose = Pose::FromVector(row.pose_cmd);
    row.leg_cmd_m = model.CompensatedLengths(pose, compensation);
    row.point_m = R * moved(pose, model.ObservationPoint(pose)) + X_TB.p_BoMo_B;
    d.rows.push_back(row);
  }
  return d;
}

}  // namespace edsp::gap
