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

nlohmann::json Slice(const double* theta, int begin, int count) {
  nlohmann::json a = nlohmann::json::array();
  for (int k = 0; k < count; ++k) a.push_back(theta[begin + k]);
  return a;
}

nlohmann::json Rows3(const double* theta, int begin) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) rows.push_back(Slice(theta, begin + 3 * i, 3));
  return rows;
}

}  // namespace

nlohmann::json ParametersJson(Effect effect, const double* t) {
  switch (effect) {
    case Effect::kPassiveRotation:
      return {{"signed_pr_scale", t[0]}, {"applied_compensation_scale", 1.0 + t[1]}};
    case Effect::kLegOffset: return {{"offset_m", Slice(t, 0, 6)}};
    case Effect::kJointPosition: return {{"base_m", Rows3(t, 0)}, {"platform_m", Rows3(t, 18)}};
    case Effect::kLeadError: return {{"epsilon", Slice(t, 0, 6)}};
    case Effect::kPeriodicLeadError: {
      nlohmann::json amplitude = nlohmann::json::array(), phase = nlohmann::json::array();
      for (int i = 0; i < 6; ++i) {
        amplitude.push_back(std::hypot(t[2 * i], t[2 * i + 1]));
        phase.push_back(std::atan2(t[2 * i + 1], t[2 * i]));
      }
      return {{"amplitude_m", amplitude}, {"phase_rad", phase}};
    }
    case Effect::kBacklash: return {{"backlash_m", Slice(t, 0, 6)}};
    case Effect::kServoLag:
      return {{"lag_s", Slice(t, 0, 6)}, {"acceleration_lag_s2", Slice(t, 6, 6)}, {"jerk_lag_s3", t[12]}};
    case Effect::kCompliance:
      return {{"mass_over_stiffness_s2", Slice(t, 0, 6)}, {"moment_over_stiffness_s2_m", Slice(t, 6, 3)}};
    case Effect::kThermalDrift:
      return {{"growth_per_travel", t[0]}, {"growth_per_travel_stroke_per_m", t[1]},
              {"growth_powered_m_per_s", t[2]}, {"growth_powered_stroke_per_s", t[3]}};
  }
  return {};
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

std::string SeparatingMeasurementFromFrame(Effect a) {
  (void)a;
  return "a repeated home pose measured from a second tracker station (the frame moves, the rig does not)";
}

}  // namespace edsp::gap
