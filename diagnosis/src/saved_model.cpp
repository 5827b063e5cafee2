#include "edsp/diagnosis/saved_model.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/measurement_data.h"

namespace edsp::gap {

DesignOptions SavedDesignOptions(const nlohmann::json& saved, const std::string& origin) {
  if (!saved.is_object() || saved.value("format", "") != "edsp-gap-model/1") {
    throw MeasurementError(origin + ": not an edsp-gap model (key \"format\" must be \"edsp-gap-model/1\")");
  }
  const auto number = [&](const char* key, double fallback) {
    if (!saved.contains(key)) return fallback;
    if (!saved[key].is_number()) throw MeasurementError(fmt::format("{}: \"{}\" must be a number", origin, key));
    return saved[key].get<double>();
  };
  DesignOptions o;
  o.thermal_time_constant_s = number("thermal_time_constant_s", o.thermal_time_constant_s);
  o.backlash_width_m = number("backlash_width_m", o.backlash_width_m);
  if (!(o.thermal_time_constant_s > 0.0)) throw MeasurementError(origin + ": thermal_time_constant_s must be > 0");
  if (!(o.backlash_width_m > 0.0 && o.backlash_width_m < 0.01)) {
    throw MeasurementError(origin + ": backlash_width_m must be in (0, 0.01) m");
  }
  o.structural_mode_hz = number("structural_mode_hz", 0.0);
  o.structural_mode_damping = number("structural_mode_damping", o.structural_mode_damping);
  if (!(o.structural_mode_hz >= 0.0 && o.structural_mode_hz <= 100.0 && o.structural_mode_damping >= 0.0 &&
        o.structural_mode_damping <= 1.0)) {
    throw MeasurementError(origin + ": structural_mode_hz must be in [0, 100] Hz, structural_mode_damping in [0, 1]");
  }
  return o;
}

std::optional<Matrix3> SavedTrackerRotation(const nlohmann::json& saved, const std::string& origin) {
  if (!saved.is_object() || !saved.contains("tracker_rotation")) return std::nullopt;
  const nlohmann::json& values = saved["tracker_rotation"];
  Matrix3 R;
  bool numbers = values.is_array() && values.size() == 9;
  for (std::size_t k = 0; numbers && k < 9; ++k) {
    numbers = values[k].is_number() && std::isfinite(values[k].get<double>());
    if (numbers) R(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3)) = values[k].get<double>();
  }
  if (!numbers || (R.transpose() * R - Matrix3::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      std::abs(R.determinant() - 1.0) > 1e-6) {
    throw MeasurementError(origin + ": \"tracker_rotation\" must be a rotation matrix, 9 numbers row by row");
  }
  return R;
}

nlohmann::json TrackerRotationJson(const Matrix3& R) {
  nlohmann::json values = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) values.push_back(R(row, col));
  }
  return values;
}

namespace {

// `key` of an entry: ParameterCount(e) finite numbers, or none at all
// (an empty vector) when `optional` and the key is absent.
Eigen::VectorXd Numbers(const nlohmann::json& entry, const char* key, Effect e, bool optional,
                        const std::string& origin) {
  const std::string name = EffectName(e);
  if (!entry.contains(key) && optional) return Eigen::VectorXd::Zero(ParameterCount(e));
  if (!entry.contains(key) || !entry[key].is_array()) {
    throw MeasurementError(fmt::format("{}: effect {} needs a \"{}\" array", origin, name, key));
  }
  std::vector<double> values;
  for (const auto& v : entry[key]) {
    if (!v.is_number())
      throw MeasurementError(fmt::format("{}: effect {} \"{}\" holds a non-number", origin, name, key));
    values.push_back(v.get<double>());
  }
  // Models saved before thermal drift had its time driver and stroke terms
  // hold the travel term alone.
  if (e == Effect::kThermalDrift && values.size() == 1) values.resize(static_cast<std::size_t>(ParameterCount(e)), 0.0);
  if (static_cast<int>(values.size()) != ParameterCount(e)) {
    throw MeasurementError(
        fmt::format("{}: effect {} needs {} parameters, has {}", origin, name, ParameterCount(e), values.size()));
  }
  for (double v : values) {
    if (!std::isfinite(v))
      throw MeasurementError(fmt::format("{}: effect {} has a non-finite \"{}\"", origin, name, key));
  }
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

// An entry's "verdict"; a file without one (saved before verdicts) holds
// identified effects. Anything else is refused, as the kinematics refuses it.
Verdict EntryVerdict(const nlohmann::json& entry, const std::string& name, const std::string& origin) {
  if (!entry.contains("verdict")) return Verdict::kIdentified;
  const nlohmann::json& given = entry["verdict"];
  const std::optional<Verdict> verdict =
      given.is_string() ? VerdictFromName(given.get<std::string>()) : std::optional<Verdict>();
  if (!verdict) {
    throw MeasurementError(fmt::format("{}: effect {} \"verdict\" {} is not identified, ambiguous or rejected", origin,
                                       name, given.dump()));
  }
  return *verdict;
}

}  // namespace

std::vector<SavedEffect> SavedAppliedEffects(const nlohmann::json& saved, const DesignOptions& options,
                                             const std::string& origin) {
  if (!saved.contains("effects") || !saved["effects"].is_array())
    throw MeasurementError(origin + ": no \"effects\" array");
  std::vector<SavedEffect> effects;
  for (const auto& entry : saved["effects"]) {
    SavedEffect s;
    const std::string name = entry.is_object() ? entry.value("name", "") : "";
    if (!ParseEffect(name, &s.effect)) throw MeasurementError(fmt::format("{}: unknown effect \"{}\"", origin, name));
    // A named effect the calibration leaves out: its share is in those applied.
    if (entry.contains("apply") && entry["apply"].is_boolean() && !entry["apply"].get<bool>()) continue;
    if (s.effect == Effect::kStructuralResonance && !(options.structural_mode_hz > 0.0)) {
      throw MeasurementError(origin + ": effect \"structural_resonance\" needs \"structural_mode_hz\" > 0");
    }
    s.verdict = EntryVerdict(entry, name, origin);
    s.theta = Numbers(entry, "theta", s.effect, false, origin);
    s.sigma = Numbers(entry, "sigma", s.effect, true, origin);
    effects.push_back(std::move(s));
  }
  return effects;
}

}  // namespace edsp::gap
