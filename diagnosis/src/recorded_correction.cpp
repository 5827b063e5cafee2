#include "edsp/diagnosis/recorded_correction.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "edsp/diagnosis/design.h"
#include "edsp/kinematics/leg_error_model.h"

namespace edsp::gap {

const char* AgainstName(Against against) { return against == Against::kNominal ? "nominal" : "calibration"; }

bool CarriesACorrection(const MeasurementData& data) {
  for (const MeasurementRow& row : data.rows) {
    if (!row.leg_corr_m.isZero(0.0)) return true;
  }
  return false;
}

MeasurementData AsCommandedNominally(const PlatformModel& model, const MeasurementData& data, double* shift_rms_m) {
  MeasurementData out = data;
  if (shift_rms_m != nullptr) *shift_rms_m = 0.0;
  if (data.rows.empty()) return out;
  std::vector<Vector3> model_points, measured;
  for (const MeasurementRow& row : data.rows) {
    model_points.push_back(model.ObservationPoint(Pose::FromVector(row.pose_cmd)));
    measured.push_back(row.point_m);
  }
  Matrix3 R;
  Vector3 t;
  EstimateFrame(model_points, measured, &R, &t);
  double sum2 = 0.0;
  for (MeasurementRow& row : out.rows) {
    if (row.leg_corr_m.isZero(0.0)) continue;
    calibration::PointSensitivity at;
    if (!calibration::PointSensitivityAt(model, Pose::FromVector(row.pose_cmd), &at)) {
      throw MeasurementError(fmt::format("{}: run \"{}\" at time_s {}: commanded pose is singular for the model",
                                         data.source, data.runs[static_cast<std::size_t>(row.run)], row.time_s));
    }
    const Vector3 shift = R * at.per_leg * row.leg_corr_m;
    row.point_m += shift;
    row.leg_cmd_m += row.leg_corr_m;
    if (row.has_encoder) row.leg_enc_m += row.leg_corr_m;
    row.leg_corr_m.setZero();
    sum2 += shift.squaredNorm();
  }
  if (shift_rms_m != nullptr) *shift_rms_m = std::sqrt(sum2 / static_cast<double>(data.rows.size()));
  return out;
}

}  // namespace edsp::gap
