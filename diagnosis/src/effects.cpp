#include "edsp/diagnosis/effects.h"

#include <cmath>
#include <utility>

#include <nlohmann/json.hpp>

namespace edsp::gap {

bool IsNestedIn(Effect simple, Effect rich) {
  static const std::pair<Effect, Effect> kNested[] = {{Effect::kLegOffset, Effect::kJointPosition}};
  for (const auto& [s, r] : kNested) {
    if (s == simple && r == rich) return true;
  }
  return false;
}

namespace {

using calibration::ParameterLayout;

// One group's values as JSON: a number, an xyz array, an array per leg, or
// per leg an xyz array.
template <typename Read>
nlohmann::json GroupJson(const ParameterGroup& g, Read read) {
  const int count = calibration::ValueCount(g);
  if (count == 1) return read(0);
  nlohmann::json values = nlohmann::json::array();
  if (g.layout == ParameterLayout::kPerLegXyz) {
    for (int leg = 0; leg < 6; ++leg) values.push_back({read(3 * leg), read(3 * leg + 1), read(3 * leg + 2)});
    return values;
  }
  for (int k = 0; k < count; ++k) values.push_back(read(k));
  return values;
}

}  // namespace

nlohmann::json ParametersJson(Effect effect, const double* theta) {
  nlohmann::json j = nlohmann::json::object();
  for (const ParameterGroup& g : ParameterGroups(effect)) {
    j[g.key] = GroupJson(g, [&](int k) { return calibration::GroupValue(g, theta, k); });
  }
  return j;
}

nlohmann::json SigmaJson(Effect effect, const double* sigma) {
  nlohmann::json j = nlohmann::json::object();
  for (const ParameterGroup& g : ParameterGroups(effect)) {
    if (!calibration::HasSigma(g)) continue;
    j[g.key] = GroupJson(g, [&](int k) { return sigma[calibration::ThetaIndex(g, k)]; });
  }
  return j;
}

std::string SeparatingMeasurement(Effect a, Effect b) {
  auto is = [&](Effect x, Effect y) { return (a == x && b == y) || (a == y && b == x); };
  if (is(Effect::kPassiveRotation, Effect::kJointPosition)) {
    return "a yaw sweep (±30° about z at home height): PR moves all legs alike, joint errors do not";
  }
  if (is(Effect::kBacklash, Effect::kServoLag)) {
    return "a two-direction approach to the same poses at very low speed: backlash stays, lag vanishes";
  }
  if (is(Effect::kLegOffset, Effect::kJointPosition)) {
    return "poses spread over the whole workspace (rotations as well as translations)";
  }
  if (a == Effect::kCompliance || b == Effect::kCompliance) {
    return "the same motions with a second payload: only compliance scales with the load";
  }
  if (a == Effect::kServoLag || b == Effect::kServoLag) {
    return "a speed sweep (the same motion at two or three speeds): only servo lag scales with speed";
  }
  if (a == Effect::kThermalDrift || b == Effect::kThermalDrift) {
    return "a repeated home pose between motions: only thermal drift changes with time";
  }
  if (a == Effect::kBacklash || b == Effect::kBacklash) {
    return "a two-direction approach to the same poses: only backlash flips with direction";
  }
  return "motions of every axis over the full stroke, with a repeated home pose";
}

}  // namespace edsp::gap
