// The drift report the panel shows: a report as edsp-gap drift writes it is
// served as JSON; no file named, none there yet or an empty one (being
// written), something that is not a plain file of a report's size, a file
// that is not JSON or not a drift report are each answered with why,
// naming the file.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/web/drift_report_page.h"
#include "scratch_dir.h"  // tests/support

namespace edsp::web {
namespace {

std::string Written(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

// docs/interfaces.md's example of `edsp-gap drift --json`.
constexpr const char* kReport = R"({
  "legs_changed": [{"leg": 4, "change_m": 37.7e-6, "sigma_m": 6.8e-6, "z": 5.5, "at_a_m": 18e-6}],
  "changed": [{"effect": "backlash", "parameter": "backlash_m", "index": 2, "leg": 3, "before": 22e-6,
               "after": 37e-6, "change": 15e-6, "sigma": 2e-6, "z": 7.5, "at_a_m": 5e-6, "applied": true}],
  "appeared": ["compliance"], "vanished": [], "heldout_rms_m": 0.0, "recalibrate": false})";

TEST(DriftReportPage, AReportIsServedAsTheJsonItIs) {
  const std::string dir = test_support::ScratchDir("web_drift_1");
  const DriftReportAnswer answer = DriftReportPage(Written(dir + "/drift.json", kReport));
  ASSERT_EQ(answer.http_status, 200) << answer.body;
  EXPECT_EQ(nlohmann::json::parse(answer.body), nlohmann::json::parse(kReport));
}

TEST(DriftReportPage, WhatIsNoReportIsAnsweredWithWhyNamingTheFile) {
  const std::string dir = test_support::ScratchDir("web_drift_2");
  EXPECT_EQ(DriftReportPage("").http_status, 404);
  EXPECT_NE(DriftReportPage("").body.find("--drift-report"), std::string::npos);

  const DriftReportAnswer absent = DriftReportPage(dir + "/not-yet.json");
  EXPECT_EQ(absent.http_status, 404);
  EXPECT_NE(absent.body.find(dir + "/not-yet.json"), std::string::npos) << absent.body;

  const DriftReportAnswer empty = DriftReportPage(Written(dir + "/empty.json", ""));
  EXPECT_EQ(empty.http_status, 404);  // `edsp-gap drift --json > FILE` still writing
  EXPECT_NE(empty.body.find("empty"), std::string::npos) << empty.body;
  EXPECT_EQ(DriftReportPage(dir).http_status, 422);  // a directory, say
  EXPECT_EQ(DriftReportPage(Written(dir + "/huge.json", std::string(2 << 20, ' '))).http_status, 422);

  for (const std::string& text : {std::string("{\"recalibrate\": tru"), std::string("[1, 2]")}) {
    const DriftReportAnswer bad = DriftReportPage(Written(dir + "/bad.json", text));
    EXPECT_EQ(bad.http_status, 422) << text;
    EXPECT_NE(bad.body.find(dir + "/bad.json"), std::string::npos) << bad.body;
  }
  nlohmann::json model = nlohmann::json::parse(kReport);
  model.erase("recalibrate");  // a model file, say, named by mistake
  const DriftReportAnswer foreign = DriftReportPage(Written(dir + "/model.json", model.dump()));
  EXPECT_EQ(foreign.http_status, 422);
  EXPECT_NE(foreign.body.find("\"recalibrate\""), std::string::npos) << foreign.body;
}

}  // namespace
}  // namespace edsp::web
