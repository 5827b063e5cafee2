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

}  // namespace

Pose ParsePoseText(const std::string& text) {
  static const char* kNames[] = {"x", "y", "z", "roll", "pitch", "yaw"};
  const std::vector<std::string> fields = SplitCommas(text);
  if (fields.size() != 6) {
    throw std::invalid_argument(fmt::format(
        "pose \"{}\": want exactly six values x,y,z,roll,pitch,yaw (m, rad), got {}", text,
        fields.size()));
  }
  Vector6 q;
  for (int i = 0; i < 6; ++i) {
    const std::string& field = fields[static_cast<std::size_t>(i)];
    char* end = nullptr;
    const double value = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0' || !std::isfinite(value)) {
      throw std::invalid_argument(fmt::format(
          "pose \"{}\": {} = \"{}\" is not a finite number", text, kNames[i], field));
    }
    q(i) = value;
  }
  return Pose::FromVector(q);
}

}  // namespace edsp
