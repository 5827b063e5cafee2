#pragma once
// The kinematics' own values read from a config section (edsp/config_file):
// a point [x, y, z], six of them (one per leg), one number per leg. Errors
// name the file, line, section and key as every config read does.

#include <array>
#include <string_view>

#include "edsp/config_file/config_file.h"
#include "edsp/kinematics/types.h"

namespace edsp {

// [x, y, z]; absent: `fallback`.
Vector3 ReadVector3(const ConfigSection& section, std::string_view key, const Vector3& fallback);
// An array of 6 rows [x, y, z], returned as one column per leg; false (and
// `out` untouched) if absent.
bool ReadLegRows(const ConfigSection& section, std::string_view key, Matrix36* out);
// One number for every leg, or an array of 6; absent: `fallback`.
std::array<double, 6> ReadPerLeg(const ConfigSection& section, std::string_view key,
                                 const std::array<double, 6>& fallback);

}  // namespace edsp
