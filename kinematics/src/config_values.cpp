#include "edsp/kinematics/config_values.h"

#include <fmt/format.h>

namespace edsp {

Vector3 ReadVector3(const ConfigSection& section, std::string_view key, const Vector3& fallback) {
  if (!section.Has(key)) return fallback;
  if (section.ArrayLength(key) != 3) section.Fail(key, fmt::format("{} {} must be [x, y, z]", section.label(), key));
  const std::vector<double> xyz = section.Numbers(key, 3);
  return Vector3(xyz[0], xyz[1], xyz[2]);
}

bool ReadLegRows(const ConfigSection& section, std::string_view key, Matrix36* out) {
  if (!section.Has(key)) return false;
  const std::vector<std::vector<double>> rows = section.Rows(key, kNumLegs, 3);
  for (int i = 0; i < kNumLegs; ++i) {
    const std::vector<double>& row = rows[static_cast<std::size_t>(i)];
    out->col(i) = Vector3(row[0], row[1], row[2]);
  }
  return true;
}

std::array<double, 6> ReadPerLeg(const ConfigSection& section, std::string_view key,
                                 const std::array<double, 6>& fallback) {
  if (!section.Has(key)) return fallback;
  const std::vector<double> values = section.NumberOrNumbers(key, 6, 0.0);
  std::array<double, 6> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = values[i];
  return out;
}

}  // namespace edsp
