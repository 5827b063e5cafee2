#include "edsp/drives/csp_axes.h"

#include <algorithm>

namespace edsp::cia402 {

BoundedSpeedAxis::BoundedSpeedAxis(double max_speed_counts_s, double position)
    : max_speed_counts_s_(max_speed_counts_s), position_(position) {}

AxisReading BoundedSpeedAxis::Step(double dt_s, const AxisDemand& demand) {
  const double before = position_;
  if (demand.follow) {
    const double step = max_speed_counts_s_ * dt_s;
    position_ += std::clamp(static_cast<double>(demand.target) - position_, -step, step);
  }
  AxisReading r;
  r.position = position_;
  r.velocity = dt_s > 0.0 ? (position_ - before) / dt_s : 0.0;
  return r;
}

SimulatedAxes::SimulatedAxes(double max_speed_counts_s, double position)
    : axes_{BoundedSpeedAxis(max_speed_counts_s, position), BoundedSpeedAxis(max_speed_counts_s, position),
            BoundedSpeedAxis(max_speed_counts_s, position), BoundedSpeedAxis(max_speed_counts_s, position),
            BoundedSpeedAxis(max_speed_counts_s, position), BoundedSpeedAxis(max_speed_counts_s, position)} {
  for (AxisReading& r : readings_) r.position = position;
}

void SimulatedAxes::Step(double dt_s, std::int64_t /*command_utime*/,
                         const std::array<AxisDemand, kCabinetDrives>& demands) {
  for (std::size_t d = 0; d < axes_.size(); ++d) readings_[d] = axes_[d].Step(dt_s, demands[d]);
}

}  // namespace edsp::cia402
