// edsp.gap's core: edsp-gap's diagnose and evaluate on measurement files
// (CSV of interfaces.md §3 or edsp LCM logs) and CSV text, their results as
// the JSON edsp-gap prints (python/edsp/gap.py parses it).
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bindings.h"
#include "edsp/diagnosis/measurement_data.h"
#include "edsp/diagnosis/recorded_correction.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/config.h"

namespace edsp::python {

namespace {

// (origin, CSV text) pairs: data given as arrays, written as CSV by Python.
using CsvTexts = std::vector<std::pair<std::string, std::string>>;

gap::MeasurementData Measurements(const std::vector<std::string>& paths, const CsvTexts& texts,
                                  gap::TimingEvents timing) {
  gap::MeasurementData data;
  for (const std::string& path : paths) gap::AppendMeasurement(&data, gap::LoadMeasurement(path, timing));
  for (const auto& [origin, text] : texts)
    gap::AppendMeasurement(&data, gap::ParseMeasurementCsv(text, origin, timing));
  return data;
}

struct DiagnoseKnobs {
  std::optional<double> max_rate_hz, thermal_time_constant_s, structural_mode_hz, structural_mode_damping;
  bool against_calibration = false;
};

// (the report of `edsp-gap diagnose --json`, the model `--save-model` writes).
std::pair<std::string, std::string> Diagnose(const std::string& config, const std::vector<std::string>& paths,
                                             const CsvTexts& texts, const DiagnoseKnobs& knobs) {
  py::gil_scoped_release release;
  const PlatformModel model(LoadConfigFile(config));
  gap::DiagnoseOptions options;
  if (knobs.max_rate_hz) options.max_rate_hz = *knobs.max_rate_hz;
  if (knobs.thermal_time_constant_s) {
    options.design.thermal_time_constant_s = *knobs.thermal_time_constant_s;
    options.thermal_time_constants_s.clear();  // fixed, as edsp-gap's option
  }
  if (knobs.structural_mode_hz) options.design.structural_mode_hz = *knobs.structural_mode_hz;
  if (knobs.structural_mode_damping) options.design.structural_mode_damping = *knobs.structural_mode_damping;
  if (knobs.against_calibration) options.against = gap::Against::kCalibration;
  const gap::MeasurementData data = Measurements(paths, texts, gap::TimingEvents::kLeaveOut);
  const gap::Diagnosis d = gap::Diagnose(model, data, options);
  // Increments on a calibration in force are no model to apply alone (as
  // edsp-gap's --save-model refuses them): none.
  const bool increments = knobs.against_calibration && gap::CarriesACorrection(data);
  return {gap::ToJson(d).dump(), increments ? std::string() : gap::ModelJson(d).dump(2)};
}

// The JSON of `edsp-gap evaluate --json`.
std::string Evaluate(const std::string& config, const std::string& model_json, const std::string& model_origin,
                     const std::vector<std::string>& paths, const CsvTexts& texts, bool keep_timing_events) {
  py::gil_scoped_release release;
  const PlatformModel model(LoadConfigFile(config));
  nlohmann::json saved;
  try {
    saved = nlohmann::json::parse(model_json);
  } catch (const nlohmann::json::parse_error& e) {
    throw gap::MeasurementError(model_origin + ": not JSON (" + e.what() + ")");
  }
  const gap::TimingEvents timing = keep_timing_events ? gap::TimingEvents::kKeep : gap::TimingEvents::kLeaveOut;
  return gap::ToJson(gap::Evaluate(model, Measurements(paths, texts, timing), saved, model_origin)).dump();
}

}  // namespace

void BindGap(py::module_& m) {
  // Bad data, models and configs are the caller's values: ValueError.
  py::register_exception<gap::MeasurementError>(m, "MeasurementError", PyExc_ValueError);
  py::register_exception<calibration::CalibrationError>(m, "CalibrationError", PyExc_ValueError);
  py::register_exception<ConfigError>(m, "ConfigError", PyExc_ValueError);
  m.def(
      "gap_diagnose",
      [](const std::string& config, const std::vector<std::string>& paths, const CsvTexts& texts,
         std::optional<double> max_rate_hz, std::optional<double> thermal_time_constant_s,
         std::optional<double> structural_mode_hz, std::optional<double> structural_mode_damping,
         bool against_calibration) {
        return Diagnose(
            config, paths, texts,
            {max_rate_hz, thermal_time_constant_s, structural_mode_hz, structural_mode_damping, against_calibration});
      },
      py::arg("config"), py::arg("paths"), py::arg("texts"), py::arg("max_rate_hz"), py::arg("thermal_time_constant_s"),
      py::arg("structural_mode_hz"), py::arg("structural_mode_damping"), py::arg("against_calibration"));
  m.def("gap_evaluate", &Evaluate, py::arg("config"), py::arg("model_json"), py::arg("model_origin"), py::arg("paths"),
        py::arg("texts"), py::arg("keep_timing_events"));
}

}  // namespace edsp::python
