#include "edsp/cueing/platform_motion.h"

#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>

namespace edsp {

VehicleSeries PlatformMotionAtHead(const std::vector<Pose>& poses, double period_s, const Vector3& head_in_platform_m) {
  if (poses.size() < 3) {
    throw std::invalid_argument(fmt::format("the platform's motion needs at least 3 poses, got {}", poses.size()));
  }
  const std::size_t n = poses.size();
  std::vector<Matrix3> rotation(n);
  std::vector<Vector3> head(n);
  for (std::size_t k = 0; k < n; ++k) {
    rotation[k] = RotationFromRpy(poses[k].rpy_rad);
    head[k] = poses[k].p_BoMo_B + rotation[k] * head_in_platform_m;
  }
  const Vector3 gravity(0.0, 0.0, -kStandardGravity_m_s2);
  VehicleSeries series;
  series.period_s = period_s;
  series.samples.resize(n);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Vector3 acceleration = (head[k + 1] - 2.0 * head[k] + head[k - 1]) / (period_s * period_s);
    const Eigen::AngleAxisd turn(Matrix3(rotation[k + 1] * rotation[k - 1].transpose()));
    const Vector3 omega_B = turn.axis() * turn.angle() / (2.0 * period_s);
    VehicleSample& sample = series.samples[k];
    sample.t_s = static_cast<double>(k) * period_s;
    sample.specific_force_m_s2 = rotation[k].transpose() * (acceleration - gravity);
    sample.angular_velocity_rad_s = rotation[k].transpose() * omega_B;
  }
  series.samples.front() = series.samples[1];
  series.samples.front().t_s = 0.0;
  series.samples.back() = series.samples[n - 2];
  series.samples.back().t_s = static_cast<double>(n - 1) * period_s;
  return series;
}

}  // namespace edsp
