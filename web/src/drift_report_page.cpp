#include "edsp/web/drift_report_page.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace edsp::web {

namespace {

// What every `edsp-gap drift --json` holds (docs/interfaces.md, §4a), and
// the panel shows.
constexpr const char* kDriftKeys[] = {"recalibrate", "legs_changed", "changed",
                                      "appeared",    "vanished",     "heldout_rms_m"};

}  // namespace

DriftReportAnswer DriftReportPage(const std::string& file) {
  if (file.empty()) return {404, "edsp-web serves no drift report: --drift-report FILE names one"};
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    return {404, "drift report " + file + ": not there (yet): edsp-gap drift --json writes it"};
  }
  std::ostringstream text;
  text << in.rdbuf();
  const nlohmann::json report = nlohmann::json::parse(text.str(), nullptr, false);
  if (report.is_discarded() || !report.is_object()) {
    return {422, "drift report " + file + ": not a JSON object (is it edsp-gap drift --json's output?)"};
  }
  for (const char* key : kDriftKeys) {
    if (!report.contains(key)) {
      return {422, "drift report " + file + ": no \"" + key + "\" (is it edsp-gap drift --json's output?)"};
    }
  }
  return {200, report.dump()};
}

}  // namespace edsp::web
