// The measurement CSV of interfaces.md §3 as the diagnosis reads it: any
// column order, comments, unknown columns, optional encoders; bad files
// named with file, line and column; edsp logs read through the exporter.
#include <fstream>

#include <gtest/gtest.h>

#include "edsp/diagnosis/measurement_data.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "log_builder.h"

namespace edsp::gap {
namespace {

const char* kHeader =
    "point_z_m,time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
    "pose_cmd_yaw_rad,leg_cmd_1_m,leg_cmd_2_m,leg_cmd_3_m,leg_cmd_4_m,leg_cmd_5_m,leg_cmd_6_m,"
    "extra,point_x_m,point_y_m\n";

std::string Row(double t, const char* run, const char* z = "1.5") {
  return std::string(z) + "," + std::to_string(t) + "," + run + ",0,0,1.511,0,0,0,1.9,1.9,1.9,1.9,1.9,1.9,junk,1.2,0\n";
}

TEST(MeasurementCsv, AnyColumnOrderCommentsAndUnknownColumns) {
  const MeasurementData d = ParseMeasurementCsv(
      std::string("# exported by a tracker\n") + kHeader + Row(0.0, "Lz") + Row(0.01, "Lz") + "\n" + Row(0.0, "Rz"),
      "t.csv");
  ASSERT_EQ(d.rows.size(), 3u);
  EXPECT_EQ(d.runs, (std::vector<std::string>{"Lz", "Rz"}));
  EXPECT_EQ(d.rows[2].run, 1);
  EXPECT_DOUBLE_EQ(d.rows[1].point_m.z(), 1.5);
  EXPECT_DOUBLE_EQ(d.rows[1].point_m.x(), 1.2);
  EXPECT_DOUBLE_EQ(d.rows[0].pose_cmd(2), 1.511);
  EXPECT_FALSE(d.rows[0].has_encoder);
}

void ExpectError(const std::string& text, const std::string& fragment) {
  try {
    ParseMeasurementCsv(text, "bad.csv");
    ADD_FAILURE() << "accepted: " << fragment;
  } catch (const MeasurementError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(MeasurementCsv, BadCellsAreNamedByFileLineAndColumn) {
  ExpectError(std::string(kHeader) + Row(0.0, "Lz", "abc"), "bad.csv:2:1: point_z_m \"abc\" is not a number");
  ExpectError(std::string(kHeader) + Row(0.0, "Lz", "nan"), "bad.csv:2:1: point_z_m is nan (not finite)");
  ExpectError(std::string(kHeader) + Row(0.0, "Lz", "inf"), "not finite");
  ExpectError(std::string(kHeader) + Row(0.5, "Lz") + Row(0.1, "Lz"),
              "bad.csv:3:5: time_s 0.1 goes back in run \"Lz\"");
  ExpectError(std::string(kHeader) + "1.5,0,Lz,0\n", "bad.csv:2: row has 4 fields");
  ExpectError("time_s,run\n0,Lz\n", "bad.csv:1: header lacks the required column \"pose_cmd_x_m\"");
  ExpectError("# only a comment\n", "no header row");
  ExpectError(kHeader, "a header but no data rows");
}

TEST(MeasurementCsv, EncodersAreOptionalPerFile) {
  std::string header =
      "time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
      "pose_cmd_yaw_rad,leg_cmd_1_m,leg_cmd_2_m,leg_cmd_3_m,leg_cmd_4_m,leg_cmd_5_m,leg_cmd_6_m,"
      "leg_enc_1_m,leg_enc_2_m,leg_enc_3_m,leg_enc_4_m,leg_enc_5_m,leg_enc_6_m,point_x_m,point_y_m,point_z_m\n";
  const MeasurementData d = ParseMeasurementCsv(header +
                                                    "0,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,1.1,1.1,1.1,1.1,1.1,1.1,1,2,3\n"
                                                    "0.1,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,,,,,,,1,2,3\n",
                                                "enc.csv");
  EXPECT_TRUE(d.rows[0].has_encoder);
  EXPECT_DOUBLE_EQ(d.rows[0].leg_enc_m(5), 1.1);
  EXPECT_FALSE(d.rows[1].has_encoder);
}

// leg_corr_*_m (a calibration's correction recorded with the command): read
// when all six are there, an empty cell a zero; five of six are refused by
// the one missing, as a zero there would be a wrong nominal residual.
TEST(MeasurementCsv, CorrectionColumnsAreAllSixOrNone) {
  const std::string header =
      "time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
      "pose_cmd_yaw_rad,leg_cmd_1_m,leg_cmd_2_m,leg_cmd_3_m,leg_cmd_4_m,leg_cmd_5_m,leg_cmd_6_m,"
      "point_x_m,point_y_m,point_z_m,leg_corr_1_m,leg_corr_2_m,leg_corr_3_m,leg_corr_4_m,"
      "leg_corr_5_m";
  const MeasurementData d = ParseMeasurementCsv(header +
                                                    ",leg_corr_6_m\n"
                                                    "0,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,1,2,3,1e-4,0,0,0,0,-2e-5\n"
                                                    "0.1,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,1,2,3,,,,,,\n",
                                                "corr.csv");
  EXPECT_TRUE(d.has_correction);
  EXPECT_DOUBLE_EQ(d.rows[0].leg_corr_m(0), 1e-4);
  EXPECT_DOUBLE_EQ(d.rows[0].leg_corr_m(5), -2e-5);
  EXPECT_TRUE(d.rows[1].leg_corr_m.isZero(0.0));
  EXPECT_FALSE(ParseMeasurementCsv(std::string(kHeader) + Row(0.0, "Lz"), "t.csv").has_correction);
  ExpectError(header + "\n0,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,1,2,3,0,0,0,0,0\n",
              "bad.csv:1: header has 5 of the six leg_corr columns but lacks \"leg_corr_6_m\"");
  ExpectError(header + ",leg_corr_6_m\n0,Lz,0,0,1.511,0,0,0,1,1,1,1,1,1,1,2,3,1e-4,,,,,\n",
              "bad.csv:2:45: leg_corr_2_m is empty beside 1 given");
}

// `timing_event` (edsp-log's export: near a stall of the controller): a
// row flagged 1 is left out and counted, 0 or empty is kept; anything else
// is named, and a file of nothing but flagged rows is no measurement.
TEST(MeasurementCsv, RowsFlaggedTimingEventAreLeftOutAndCounted) {
  const std::string header = std::string(kHeader).insert(std::string(kHeader).size() - 1, ",timing_event");
  auto row = [](double t, const char* flag) {
    std::string r = Row(t, "Lz");
    return r.insert(r.size() - 1, std::string(",") + flag);
  };
  const MeasurementData d =
      ParseMeasurementCsv(header + row(0.0, "0") + row(0.1, "1") + row(0.2, "") + row(0.3, "1"), "t.csv");
  ASSERT_EQ(d.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(d.rows[1].time_s, 0.2);
  EXPECT_EQ(d.timing_excluded, 2);
  EXPECT_EQ(Decimated(d, 100.0).timing_excluded, 2);
  EXPECT_EQ(d.timing_kept, 0);
  // Kept on request (edsp-gap --keep-timing-events): every row, none left
  // out, and how many were flagged still said.
  const MeasurementData kept = ParseMeasurementCsv(
      header + row(0.0, "0") + row(0.1, "1") + row(0.2, "") + row(0.3, "1"), "t.csv", TimingEvents::kKeep);
  EXPECT_EQ(kept.rows.size(), 4u);
  EXPECT_EQ(kept.timing_excluded, 0);
  EXPECT_EQ(kept.timing_kept, 2);
  EXPECT_EQ(Decimated(kept, 100.0).timing_kept, 2);
  ExpectError(header + row(0.0, "2"), "bad.csv:2:68: timing_event 2 is neither 0 nor 1");
  ExpectError(header + row(0.0, "yes"), "timing_event \"yes\" is not a number");
  ExpectError(header + row(0.0, "1"), "every one of its 1 rows is flagged timing_event");
}

TEST(MeasurementCsv, DecimationKeepsEveryRunAtMostAtTheRate) {
  std::string text = kHeader;
  for (int k = 0; k < 100; ++k) text += Row(k * 0.001, "Lz");
  for (int k = 0; k < 100; ++k) text += Row(k * 0.001, "Rz");
  const MeasurementData d = Decimated(ParseMeasurementCsv(text, "t.csv"), 100.0);
  EXPECT_EQ(d.rows.size(), 20u);  // 0.1 s of 1 kHz per run at 100 Hz
}

TEST(MeasurementCsv, SameRunNamesFromTwoFilesStayApart) {
  MeasurementData a = ParseMeasurementCsv(std::string(kHeader) + Row(0, "Lz"), "/d/a.csv");
  AppendMeasurement(&a, ParseMeasurementCsv(std::string(kHeader) + Row(0, "Lz") + Row(0, "Rz"), "/d/b.csv"));
  EXPECT_EQ(a.runs, (std::vector<std::string>{"Lz", "Lz@b.csv", "Rz"}));
  EXPECT_EQ(a.rows[2].run, 2);
}

TEST(MeasurementLog, AnEdspLogIsReadThroughTheExporter) {
  const std::string path = testing::TempDir() + "/gap_input.lcmlog";
  {
    test_support::LogBuilder log(path);
    pose_setpoint_t sp{};
    sp.trajectory = "Lz/move 1";
    sp.pose[2] = 1.511;
    leg_command_t c{};
    for (int i = 0; i < 6; ++i) {
      c.command_length_m[i] = 1.9;
      c.pr_correction_m[i] = 2e-4;
      c.ik_length_m[i] = 1.9 + 2e-4 + (i == 0 ? 1e-4 : 0.0);  // a calibration took 0.1 mm off leg 1
    }
    tracker_point_t t{};
    t.valid = 1;
    t.point_m[0] = 1.2;
    t.point_m[2] = 1.511;
    log.Add("EDSP_SETPOINT", sp);
    log.Add("EDSP_LEG_COMMAND", c);
    for (int k = 0; k < 3; ++k) {
      t.utime = 1000 * k;
      log.Add("EDSP_TRACKER", t);
    }
    log.AddBytes("EDSP_TRACKER", {1, 2, 3});  // truncated: skipped, not fatal
  }
  const MeasurementData d = LoadMeasurement(path);
  ASSERT_EQ(d.rows.size(), 3u);
  EXPECT_EQ(d.runs, std::vector<std::string>{"Lz"});
  EXPECT_DOUBLE_EQ(d.rows[2].time_s, 0.002);
  EXPECT_DOUBLE_EQ(d.rows[0].leg_cmd_m(3), 1.9);
  EXPECT_TRUE(d.has_correction);
  EXPECT_NEAR(d.rows[0].leg_corr_m(0), 1e-4, 1e-15);
  EXPECT_NEAR(d.rows[0].leg_corr_m.tail<5>().norm(), 0.0, 1e-15);
}

TEST(MeasurementLog, MissingFileIsNamed) {
  try {
    LoadMeasurement("/nonexistent/run.csv");
    FAIL();
  } catch (const MeasurementError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run.csv: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace edsp::gap
