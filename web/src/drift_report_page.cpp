#include "edsp/web/drift_report_page.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

namespace edsp::web {

namespace {

// What every `edsp-gap drift --json` holds (docs/interfaces.md, §4a), and
// the panel shows.
constexpr std::uintmax_t kMaxDriftReportBytes = 1 << 20;  // a drift report is a few kB

constexpr const char* kDriftKeys[] = {"recalibrate", "legs_changed", "changed",
                                      "appeared",    "vanished",     "heldout_rms_m"};

}  // namespace

DriftReportAnswer DriftReportPage(const std::string& file) {
  if (file.empty()) return {404, "edsp-web serves no drift report: --drift-report FILE names one"};
  // Read on the server's one thread: a plain file of a report's size only
  // (a FIFO or a huge file would hold every client, halts included).
  std::error_code error;
  if (!std::filesystem::exists(file, error)) {
    return {404, "drift report " + file + ": not there (yet): edsp-gap drift --json writes it"};
  }
  if (!std::filesystem::is_regular_file(file, error)) {
    return {422, "drift report " + file + ": not a regular file"};
  }
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (error || size > kMaxDriftReportBytes) {
    return {422, "drift report " + file + ": " + std::to_string(size) + " bytes, more than a report's " +
                     std::to_string(kMaxDriftReportBytes)};
  }
  if (size == 0) return {404, "drift report " + file + ": empty (being written?)"};
  std::ifstream in(file, std::ios::binary);
  if (!in) return {404, "drift report " + file + ": cannot be read"};
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
