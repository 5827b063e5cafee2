#include "edsp/drives/csp_image.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace edsp::cia402 {
namespace {

std::optional<std::int32_t> ToInt32(double value) {
  if (!std::isfinite(value)) return std::nullopt;
  const double rounded = std::nearbyint(value);
  if (rounded < static_cast<double>(std::numeric_limits<std::int32_t>::min()) ||
      rounded > static_cast<double>(std::numeric_limits<std::int32_t>::max())) {
    return std::nullopt;
  }
  return static_cast<std::int32_t>(rounded);
}

}  // namespace

std::optional<std::string> DriveScaling::Problem() const {
  if (!std::isfinite(counts_per_rad) || counts_per_rad <= 0.0) {
    return fmt::format("counts_per_rad must be a positive number, not {}", counts_per_rad);
  }
  if (direction != 1 && direction != -1) return fmt::format("direction must be 1 or -1, not {}", direction);
  return std::nullopt;
}

double DriveScaling::Counts(double angle_rad) const {
  return static_cast<double>(offset_counts) + direction * counts_per_rad * angle_rad;
}

double DriveScaling::CountRate(double rate_rad_s) const { return direction * counts_per_rad * rate_rad_s; }

std::optional<std::int32_t> DriveScaling::ToCounts(double angle_rad) const { return ToInt32(Counts(angle_rad)); }

std::optional<std::int32_t> DriveScaling::ToCountsPerSecond(double rate_rad_s) const {
  return ToInt32(CountRate(rate_rad_s));
}

double DriveScaling::ToAngle(std::int32_t counts) const {
  return static_cast<double>(static_cast<std::int64_t>(counts) - offset_counts) / (direction * counts_per_rad);
}

double DriveScaling::ToRate(std::int32_t counts_per_s) const {
  return static_cast<double>(counts_per_s) / (direction * counts_per_rad);
}

}  // namespace edsp::cia402
