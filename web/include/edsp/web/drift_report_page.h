#pragma once
// The last `edsp-gap drift --json` verdict, served to the panel's
// calibration view at /drift-report.json when edsp-web is told its file
// (--drift-report FILE). The file is read at each request, so a verdict
// written after the server started shows at the panel's next look; what
// is not there yet, not JSON or not a drift report is answered with why,
// naming the file. A function with no socket: tested as such.

#include <string>
#include <string_view>

namespace edsp::web {

inline constexpr std::string_view kDriftReportPath = "/drift-report.json";

struct DriftReportAnswer {
  int http_status;   // 200, or 404 (no file named, none there or empty yet), 422 (not a drift report)
  std::string body;  // the report as JSON, or why not (text)
};

// `file` empty: edsp-web was given none.
DriftReportAnswer DriftReportPage(const std::string& file);

}  // namespace edsp::web
