#include "edsp/diagnosis/encoder_check.h"

#include <algorithm>

namespace edsp::gap {

double EncoderShareOfLag(const Design& d, const Eigen::VectorXd& theta) {
  const ColumnRange& r = d.Of(Effect::kServoLag);
  if (!d.has_encoder || theta.size() != r.count) return 1.0;
  const Eigen::VectorXd fit = d.columns.middleCols(r.begin, r.count) * theta;
  double along = 0.0;
  for (int k = 0; k < d.samples(); ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    // The motor's motion at A: encoder − command.
    const Vector3 encoders = -(d.point_per_leg[s] * d.servo_error_m[s]);
    along += fit.segment<3>(3 * k).dot(encoders);
  }
  const double size = fit.squaredNorm();
  return size > 0.0 ? std::min(1.0, along / size) : 1.0;
}

}  // namespace edsp::gap
