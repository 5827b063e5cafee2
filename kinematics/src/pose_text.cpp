#include "edsp/kinematics/pose_text.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace edsp {

namespace {

std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> fields(1);
  for (char c : text) {
    if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// The comma-separated finite numbers `names` name, in order.
std::vector<double> ParseNumbers(const std::string& text, const std::vector<const char*>& names, const char* what,
                                 const char* want) {
  const std::vector<std::string> fields = SplitCommas(text);
  if (fields.size() != names.size()) {
    throw std::invalid_argument(fmt::format("{} \"{}\": want exactly {} values {}, got {}", what, text,
                                            names.size() == 6 ? "six" : "three", want, fields.size()));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    char* end = nullptr;
    const double value = std::strtod(fields[i].c_str(), &end);
    if (fields[i].empty() || *end != '\0' || !std::isfinite(value)) {
      throw std::invalid_argument(
          fmt::format("{} \"{}\": {} = \"{}\" is not a finite number", what, text, names[i], fields[i]));
    }
    values.push_back(value);
  }
  return values;
}

}  // namespace

Pose ParsePoseText(const std::string& text) {
  const std::vector<double> v =
      ParseNumbers(text, {"x", "y", "z", "roll", "pitch", "yaw"}, "pose", "x,y,z,roll,pitch,yaw (m, rad)");
  Vector6 q;
  for (int i = 0; i < 6; ++i) q(i) = v[static_cast<std::size_t>(i)];
  return Pose::FromVector(q);
}

Vector3 ParsePointText(const std::string& text) {
  const std::vector<double> v = ParseNumbers(text, {"x", "y", "z"}, "point", "x,y,z (m)");
  return Vector3(v[0], v[1], v[2]);
}

}  // namespace edsp
